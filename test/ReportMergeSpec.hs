-- | @stref report merge@, through the built binary: a corpus run split in
-- three shards (@--shard I/3@), each writing its report, merges into the
-- report of the unsharded run. What legitimately differs is only the time
-- taken: the cases' @seconds@ (JSON) and every @time@ attribute (JUnit),
-- which the comparison removes. The runs cover every kind of result (pass,
-- fail, malformed case, unsupported, engine error, known failure) with a
-- test engine, and a whole area of the real corpus with the reference.
module ReportMergeSpec (spec) where

import Conformance.Paths (engineScript, fixtureCorpus, malformedCorpus, strefBinary)
import Control.Exception (bracket)
import Data.Aeson (Value (..), decode)
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (isInfixOf)
import qualified Data.Text as T
import qualified Data.Vector as V
import System.Directory (getTemporaryDirectory, removeFile)
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO (hClose, openTempFile)
import System.Process (readProcessWithExitCode)
import Test.Hspec

stref :: [String] -> IO (ExitCode, String, String)
stref args = do
  bin <- strefBinary
  readProcessWithExitCode bin args ""

-- | @n@ temporary files, removed afterwards.
withTempFiles :: Int -> ([FilePath] -> IO a) -> IO a
withTempFiles n = bracket make (mapM_ removeFile)
  where
    make = do
      tmp <- getTemporaryDirectory
      mapM (\i -> openTempFile tmp ("stref-merge-" ++ show i ++ ".report") >>= \(p, h) -> hClose h >> pure p) [1 .. n]

-- | Run the corpus unsharded and in three shards, each report to a file,
-- then merge the shards' reports: the unsharded run's (exit, report), the
-- merge's (exit, report, stdout and stderr), and the shards' reports.
shardAndMerge :: String -> [String] -> IO ((ExitCode, String), (ExitCode, String, String), [String])
shardAndMerge format args = withTempFiles 5 $ \files -> case files of
  [whole, s1, s2, s3, merged] -> do
    (wholeCode, _, _) <- stref (["conformance"] ++ args ++ ["--format", format, "--output", whole])
    mapM_ (\(i, f) -> stref (["conformance"] ++ args ++ ["--shard", show i ++ "/3", "--format", format, "--output", f])) (zip [1 :: Int ..] [s1, s2, s3])
    (mergeCode, out, err) <- stref ["report", "merge", s1, s2, s3, "--output", merged]
    wholeReport <- readFile' whole
    mergedReport <- readFile' merged
    shards <- mapM readFile' [s1, s2, s3]
    pure ((wholeCode, wholeReport), (mergeCode, mergedReport, out ++ err), shards)
  _ -> fail "five files"
  where
    readFile' p = do
      s <- readFile p
      length s `seq` pure s

-- | A JSON report without the cases' @seconds@.
withoutSeconds :: Value -> Value
withoutSeconds = \case
  Object o -> Object (fmap withoutSeconds (KM.delete "seconds" o))
  Array xs -> Array (fmap withoutSeconds xs)
  v -> v

-- | A JUnit report without its @time="..."@ attributes.
withoutTimes :: String -> String
withoutTimes = T.unpack . T.concat . dropTimes . T.splitOn " time=\"" . T.pack
  where
    dropTimes (x : rest) = x : map (T.drop 1 . T.dropWhile (/= '"')) rest
    dropTimes [] = []

caseCount' :: Maybe Value -> Int
caseCount' = maybe (-1) caseCount

caseCount :: Value -> Int
caseCount = \case
  Object o | Just (Array xs) <- KM.lookup "cases" o -> V.length xs
  _ -> -1

-- | The fixture corpus, a malformed corpus, an engine whose answers give
-- pass, fail, unsupported and engine-error, one known failure (skipped).
everyKind :: [String]
everyKind =
  [ fixtureCorpus
  , malformedCorpus
  , "--engine"
  , engineScript "mixed"
  , "--known-failures"
  , "test" </> "fixtures" </> "known-failures-mixed"
  ]

spec :: Spec
spec = describe "stref report merge" $ do
  it "merges the JSON reports of three shards into the unsharded run's report (every kind of result), exit 1 as the run" $ do
    ((wholeCode, whole), (code, merged, out), shards) <- shardAndMerge "json" everyKind
    -- the shards are shards: each holds some of the cases, none all
    map (caseCount' . decode . BL.pack) shards `shouldBe` [5, 5, 4]
    wholeCode `shouldBe` ExitFailure 1
    code `shouldBe` ExitFailure 1
    let w = decode (BL.pack whole) :: Maybe Value
        m = decode (BL.pack merged)
    fmap caseCount w `shouldBe` Just 14
    fmap withoutSeconds m `shouldBe` fmap withoutSeconds w
    -- the eight malformed cases count as failed
    lines out `shouldBe` ["1 passed, 10 failed, 1 unsupported, 1 engine-error, 1 skipped"]

  it "merges the JUnit XML reports of three shards into the unsharded run's report, apart from the times" $ do
    ((_, whole), (code, merged, out), shards) <- shardAndMerge "junit" everyKind
    map (length . filter ("<testcase " `isInfixOf`) . lines) shards `shouldBe` [5, 5, 4]
    code `shouldBe` ExitFailure 1
    withoutTimes merged `shouldBe` withoutTimes whole
    -- JUnit counts the malformed cases and the engine error as errors
    lines out `shouldBe` ["14 tests, 2 failures, 9 errors, 2 skipped (unsupported included)"]

  it "merges the shards of a whole area of the corpus run on the reference (exit 0: every case passes)" $ do
    ((wholeCode, whole), (code, merged, out), _) <- shardAndMerge "json" ["conformance/tecomat/operators", "conformance/tecomat/lexical"]
    wholeCode `shouldBe` ExitSuccess
    code `shouldBe` ExitSuccess
    let w = decode (BL.pack whole) :: Maybe Value
    fmap caseCount w `shouldSatisfy` maybe False (> 30)
    fmap withoutSeconds (decode (BL.pack merged)) `shouldBe` fmap withoutSeconds w
    out `shouldSatisfy` (" passed, 0 failed, 0 unsupported, 0 engine-error, 0 skipped" `isInfixOf`)

  it "writes the merged report on stdout without --output" $
    withTempFiles 2 $ \[a, b] -> do
      _ <- stref ["conformance", fixtureCorpus, "--shard", "1/2", "--format", "json", "--output", a]
      _ <- stref ["conformance", fixtureCorpus, "--shard", "2/2", "--format", "json", "--output", b]
      (code, out, _) <- stref ["report", "merge", a, b]
      code `shouldBe` ExitSuccess
      fmap caseCount (decode (BL.pack out)) `shouldBe` Just 6

  describe "refuses, with exit 2 and the reason" $ do
    it "reports that overlap (a shard and the whole run), and a report given twice" $
      withTempFiles 2 $ \[a, b] -> do
        _ <- stref ["conformance", fixtureCorpus, "--shard", "1/2", "--format", "json", "--output", a]
        _ <- stref ["conformance", fixtureCorpus, "--format", "json", "--output", b]
        (code, _, err) <- stref ["report", "merge", a, b]
        code `shouldBe` ExitFailure 2
        err `shouldSatisfy` ("the case mastertool-xe/arith/int-add-saturates is in both" `isInfixOf`)
        (code', _, err') <- stref ["report", "merge", a, a]
        code' `shouldBe` ExitFailure 2
        err' `shouldSatisfy` ("is reported twice in" `isInfixOf`)
    it "the reports of different runs (engines)" $
      withTempFiles 2 $ \[a, b] -> do
        _ <- stref ["conformance", fixtureCorpus, "--shard", "1/2", "--format", "json", "--output", a]
        _ <- stref ["conformance", fixtureCorpus, "--shard", "2/2", "--format", "json", "--output", b, "--engine", engineScript "canned"]
        (code, _, err) <- stref ["report", "merge", a, b]
        code `shouldBe` ExitFailure 2
        err `shouldSatisfy` ("its engine differs" `isInfixOf`)
    it "a text report, and JSON mixed with JUnit" $
      withTempFiles 3 $ \[a, b, c] -> do
        _ <- stref ["conformance", fixtureCorpus, "--shard", "1/2", "--format", "json", "--output", a]
        _ <- stref ["conformance", fixtureCorpus, "--shard", "2/2", "--format", "junit", "--output", b]
        _ <- stref ["conformance", fixtureCorpus, "--shard", "2/2", "--output", c]
        (code1, _, err1) <- stref ["report", "merge", a, c]
        code1 `shouldBe` ExitFailure 2
        err1 `shouldSatisfy` ("not a report of stref conformance" `isInfixOf`)
        (code2, _, err2) <- stref ["report", "merge", a, b]
        code2 `shouldBe` ExitFailure 2
        err2 `shouldSatisfy` ("different formats" `isInfixOf`)
    it "a file that does not exist, and a directory" $ do
      (code, _, err) <- stref ["report", "merge", "test/fixtures/no-such-report.json"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("no such file: test/fixtures/no-such-report.json" `isInfixOf`)
      (code', _, err') <- stref ["report", "merge", "test/fixtures"]
      code' `shouldBe` ExitFailure 2
      err' `shouldSatisfy` ("test/fixtures is a directory" `isInfixOf`)
