module ConformanceRunnerSpec (spec) where

import Conformance.Paths
import Control.Monad (forM_)
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.List.NonEmpty (NonEmpty (..))
import qualified Data.Map.Strict as M
import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T
import GHC.Clock (getMonotonicTime, getMonotonicTimeNSec)
import Stref.Conformance.Case
import Stref.Conformance.Corpus
import Stref.Conformance.Protocol
import Stref.Conformance.Report
import Stref.Conformance.Runner
import Stref.Engine (referenceEngine)
import Stref.Policy (mastertoolXE)
import System.Directory (getTemporaryDirectory, removeFile)
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.Process (readProcessWithExitCode)
import Test.Hspec

fixtures :: IO Corpus
fixtures = loadCorpus [fixtureCorpus]

external :: String -> Double -> RunOptions
external cmd secs = defaultRunOptions {roEngine = External cmd, roTimeout = secs, roJobs = 5}

outcomes :: [CaseResult] -> M.Map Text Outcome
outcomes rs = M.fromList [(resId r, resOutcome r) | r <- rs]

spec :: Spec
spec = describe "Conformance runner" $ do
  describe "misbehaving engines give engine-error and the run goes on" $ do
    forM_
      [ ("hang", "sleeps for ever", "no answer within")
      , ("crash", "exits with status 3", "exited with status 3")
      , ("garbage", "prints something that is not JSON", "not a valid stref-engine/1 answer")
      , ("flood", "prints without end", "exceeds")
      ]
      $ \(script, what, reason) -> it ("an engine that " ++ what) $ do
        corpus <- fixtures
        t0 <- getMonotonicTime
        rs <- runCorpus (external (engineScript script) 2) {roMaxAnswerBytes = 1024 * 1024} corpus
        t1 <- getMonotonicTime
        length rs `shouldBe` length (corpusEntries corpus)
        forM_ rs $ \r -> case resOutcome r of
          EngineError e -> e `shouldSatisfy` T.isInfixOf reason
          o -> expectationFailure (T.unpack (resId r) ++ ": expected engine-error, got " ++ show o)
        -- six cases on five workers, each bounded by the 2 s limit
        (t1 - t0) `shouldSatisfy` (< 15)

    it "kills the engine's whole process group on timeout" $ do
      corpus <- fixtures
      -- a marker of this run, so that sleepers of other test runs do not count
      marker <- ("0." ++) . show . (`mod` 1000000000) <$> getMonotonicTimeNSec
      _ <- runCorpus (external (engineScript "hang" ++ " " ++ marker) 1) corpus
      (_, out, _) <- readProcessWithExitCode "sh" ["-c", "ps -eo args | grep -c '^sleep 1000 " ++ marker ++ "$' || true"] ""
      words out `shouldBe` ["0"]

  it "an engine's unsupported answers are counted apart" $ do
    rs <- fixtures >>= runCorpus (external (engineScript "unsupported") 5)
    totals rs `shouldBe` Totals 0 0 6 0 0
    any failing rs `shouldBe` False

  it "judges a canned engine: the case it answers right passes, the others fail" $ do
    rs <- fixtures >>= runCorpus (external (engineScript "canned") 5)
    M.lookup "mastertool-xe/arith/int-add-saturates" (outcomes rs) `shouldBe` Just Pass
    M.lookup "mastertool-xe/calls/three-calls" (outcomes rs)
      `shouldBe` Just (Fail (Difference "%M0101" "2" "not reported" :| [Difference "OUTPUT1" "false" "true"]))

  it "reports known failures as skipped and does not fail the run for them" $ do
    corpus <- fixtures
    let failingIds = S.fromList ["mastertool-xe/arith/real-rounding", "mastertool-xe/arith/real-sum", "mastertool-xe/calls/div-zero", "mastertool-xe/calls/named-vars", "mastertool-xe/calls/three-calls"]
    rs <- runCorpus (external (engineScript "canned") 5) {roKnownFailures = failingIds} corpus
    totals rs `shouldBe` Totals 1 0 0 0 5
    any failing rs `shouldBe` False
    [resId r | r <- rs, resKnownFailure r] `shouldBe` S.toList failingIds

  it "splits the cases into disjoint shards whose union is the whole" $ do
    corpus <- fixtures
    shards <- mapM (\i -> map resId <$> runCorpus (external (engineScript "unsupported") 5) {roShard = Just (i, 3)} corpus) [1, 2, 3]
    let allIds = map entryId (corpusEntries corpus)
    S.unions (map S.fromList shards) `shouldBe` S.fromList allIds
    sum (map length shards) `shouldBe` length allIds
    map length shards `shouldBe` [2, 2, 2]

  it "skips what --filter, --feature and --rule leave out" $ do
    corpus <- fixtures
    rs <- runCorpus (external (engineScript "unsupported") 5) {roFeatures = ["calls"]} corpus
    [resId r | r <- rs, Unsupported _ <- [resOutcome r]] `shouldBe` ["mastertool-xe/calls/three-calls"]
    tSkipped (totals rs) `shouldBe` 5
    rs' <- runCorpus (external (engineScript "unsupported") 5) {roRules = ["MT-OP-7"], roFilters = ["*/arith/*"]} corpus
    [resId r | r <- rs', Unsupported _ <- [resOutcome r]] `shouldBe` ["mastertool-xe/arith/int-add-saturates"]

  it "writes JUnit XML with the required elements and attributes" $ do
    rs <- fixtures >>= runCorpus (external (engineScript "canned") 5)
    let known = S.fromList ["mastertool-xe/calls/div-zero"]
        rs' = [if resId r `S.member` known then r {resOutcome = Skipped "known failure"} else r | r <- rs]
        xml = BLC.unpack (junitReport M.empty (rs' ++ [CaseResult "mastertool-xe/calls/broken" "f" Nothing (EngineError "crashed") False 0 Nothing]))
    forM_
      [ "<?xml version=\"1.0\" encoding=\"UTF-8\"?>"
      , "<testsuites name=\"stref conformance\" tests=\"7\" failures=\"4\" errors=\"1\" skipped=\"1\""
      , "<testsuite name=\"mastertool-xe/arith\" tests=\"3\" failures=\"2\" errors=\"0\" skipped=\"0\" time=\""
      , "<testcase name=\"int-add-saturates\" classname=\"mastertool-xe.arith\" time=\""
      , "<failure message=\"%M0101: expected 2, got not reported\">"
      , "<error message=\"engine-error: crashed\">"
      , "<skipped message=\"known failure\"/>"
      , "</testsuites>"
      ]
      $ \needle -> xml `shouldSatisfy` containing needle

  describe "the reference engine in-process and as `stref engine`" $ do
    it "give the same answer to every fixture request" $ do
      stref <- strefBinary
      corpus <- fixtures
      forM_ [c | Loaded c <- corpusEntries corpus] $ \c -> do
        let rq = buildRequest mastertoolXE c (effectiveExpect mastertoolXE c)
        (code, out, err) <- readProcessWithExitCode stref ["engine"] (BLC.unpack (encodeRequest rq))
        (code, err) `shouldBe` (ExitSuccess, "")
        decodeAnswer (BLC.pack out) `shouldBe` Right (referenceEngine [] rq)

    it "`stref engine --policy overflow=wrap` answers as a wrap engine" $ do
      stref <- strefBinary
      corpus <- fixtures
      let cs = [c | Loaded c <- corpusEntries corpus, caseId c == "mastertool-xe/arith/int-add-saturates"]
      forM_ cs $ \c -> do
        let rq = buildRequest mastertoolXE c (effectiveExpect mastertoolXE c)
        (_, out, _) <- readProcessWithExitCode stref ["engine", "--policy", "overflow=wrap"] (BLC.unpack (encodeRequest rq))
        -- 15000 + 25000 = 40000 wraps to 40000 - 65536 = -25536
        case decodeAnswer (BLC.pack out) of
          Right (AnswerRun _ ob) -> M.lookup "%M0012" (obOperands ob) `shouldBe` Just (SNumber (-25536))
          other -> expectationFailure ("unexpected answer " ++ show other)
      length cs `shouldBe` 1

    it "`stref conformance` passes the fixtures through `stref engine` and ends with the summary line" $ do
      stref <- strefBinary
      (code, out, _) <- readProcessWithExitCode stref ["conformance", fixtureCorpus, "--engine", stref ++ " engine", "-j", "2"] ""
      code `shouldBe` ExitSuccess
      last (lines out) `shouldBe` "6 passed, 0 failed, 0 unsupported, 0 engine-error, 0 skipped"

    it "`stref conformance` exits 1 on a failure and reads a known-failures file" $ do
      stref <- strefBinary
      (code, out, _) <- readProcessWithExitCode stref ["conformance", fixtureCorpus, "--engine", engineScript "canned"] ""
      code `shouldBe` ExitFailure 1
      last (lines out) `shouldBe` "1 passed, 5 failed, 0 unsupported, 0 engine-error, 0 skipped"
      (code', out', _) <- readProcessWithExitCode stref ["conformance", fixtureCorpus, "--engine", engineScript "canned", "--known-failures", "test/fixtures/known-failures-canned"] ""
      code' `shouldBe` ExitSuccess
      last (lines out') `shouldBe` "1 passed, 0 failed, 0 unsupported, 0 engine-error, 5 skipped"

    it "`stref conformance --format json` writes the documented report" $ do
      stref <- strefBinary
      (_, out, _) <- readProcessWithExitCode stref ["conformance", fixtureCorpus, "--engine", engineScript "canned", "--format", "json"] ""
      out `shouldSatisfy` containing "\"totals\":{"
      out `shouldSatisfy` containing "\"result\":\"fail\""
      out `shouldSatisfy` containing "\"difference\":{"
      BL.length (BLC.pack out) `shouldSatisfy` (> 0)

    it "`stref conformance --output FILE` writes the report there and the summary to stdout" $ do
      stref <- strefBinary
      tmp <- getTemporaryDirectory
      let file = tmp </> "stref-conformance-report.xml"
      (_, out, _) <- readProcessWithExitCode stref ["conformance", fixtureCorpus, "--format", "junit", "--output", file] ""
      last (lines out) `shouldBe` "6 passed, 0 failed, 0 unsupported, 0 engine-error, 0 skipped"
      xml <- readFile file
      length xml `seq` removeFile file
      xml `shouldSatisfy` containing "<testsuites name=\"stref conformance\" tests=\"6\" failures=\"0\" errors=\"0\" skipped=\"0\""
  where
    containing needle hay = T.pack needle `T.isInfixOf` T.pack hay
