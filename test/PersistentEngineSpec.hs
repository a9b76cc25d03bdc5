-- | Persistent engines (@stref conformance --persistent@, @stref engine
-- --persistent@), through the built binary: one process answers many
-- requests, one a line; a crash or a hang is the engine error of its case
-- only, and the next case is answered by a new process.
module PersistentEngineSpec (spec) where

import Conformance.Paths (engineScript, fixtureCorpus, strefBinary)
import Control.Exception (bracket)
import Data.Aeson (Value (..), decode)
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (isInfixOf)
import qualified Data.Text as T
import qualified Data.Vector as V
import System.Directory (getTemporaryDirectory, removeFile)
import System.Exit (ExitCode (..))
import System.IO (hClose, openTempFile)
import System.Process (readProcessWithExitCode)
import Test.Hspec

stref :: [String] -> String -> IO (ExitCode, String, String)
stref args input = do
  bin <- strefBinary
  readProcessWithExitCode bin args input

-- | Each case of a JSON report: (id, result, detail).
results :: String -> [(String, String, String)]
results out = case decode (BL.pack out) of
  Just (Object o) | Just (Array cs) <- KM.lookup "cases" o -> [(text "id" c, text "result" c, text "detail" c) | Object c <- V.toList cs]
  _ -> []
  where
    text k c = case KM.lookup k c of
      Just (String s) -> T.unpack s
      _ -> ""

spec :: Spec
spec = describe "persistent engines" $ do
  it "stref engine --persistent answers one request a line, each as stref engine answers it alone, until the end of its input" $ do
    let cases = ["conformance/tecomat/operators/int-addition-overflow.st", "conformance/mastertool-xe/operators/dint-add-saturates-high.st"]
    requests <- mapM (\c -> (\(_, out, _) -> out) <$> stref ["request", c] "") cases
    alone <- mapM (\rq -> (\(_, out, _) -> out) <$> stref ["engine"] rq) requests
    -- a blank line between requests is skipped
    (code, out, _) <- stref ["engine", "--persistent"] (concatMap (++ "\n") requests)
    code `shouldBe` ExitSuccess
    lines out `shouldBe` concatMap lines alone
    length (lines out) `shouldBe` 2

  it "one process answers case after case; a crash and a hang are the engine errors of their cases, and a new process answers the next" $ do
    tmp <- getTemporaryDirectory
    bracket (openTempFile tmp "stref-persistent.starts" >>= \(p, h) -> hClose h >> pure p) removeFile $ \starts -> do
      (code, out, _) <- stref ["conformance", fixtureCorpus, "--engine", engineScript "persistent" ++ " " ++ starts, "--persistent", "--timeout", "3", "--format", "json"] ""
      code `shouldBe` ExitFailure 1
      [(i, r) | (i, r, _) <- results out]
        `shouldBe` [ ("mastertool-xe/arith/int-add-saturates", "pass")
                   , ("mastertool-xe/arith/real-rounding", "fail")
                   , ("mastertool-xe/arith/real-sum", "fail")
                   , ("mastertool-xe/calls/div-zero", "engine-error")
                   , -- answered (wrongly, as the engine answers everything)
                     -- by the process started after the crash
                     ("mastertool-xe/calls/named-vars", "fail")
                   , ("mastertool-xe/calls/three-calls", "engine-error")
                   ]
      let detail i = head ([d | (i', _, d) <- results out, i' == i] ++ [""])
      detail "mastertool-xe/calls/div-zero" `shouldSatisfy` ("the engine exited with status 3; stderr: crashed on div-zero" `isInfixOf`)
      detail "mastertool-xe/calls/three-calls" `shouldSatisfy` ("no answer within 3" `isInfixOf`)
      -- the first process answered the first four cases, the second the last two
      started <- readFile starts
      length (lines started) `shouldBe` 2

  it "runs the corpus through stref engine --persistent with the results of the reference, with -j 2" $ do
    bin <- strefBinary
    let paths = ["conformance/tecomat/operators", "conformance/mastertool-xe/operators"]
    (code, out, _) <- stref (["conformance"] ++ paths ++ ["--engine", bin ++ " engine --persistent", "--persistent", "-j", "2", "--format", "json"]) ""
    (_, reference, _) <- stref (["conformance"] ++ paths ++ ["--format", "json"]) ""
    code `shouldBe` ExitSuccess
    length (results out) `shouldSatisfy` (> 50)
    [(i, r) | (i, r, _) <- results out] `shouldBe` [(i, r) | (i, r, _) <- results reference]

  it "stops with one message (exit 2) when the engine cannot be started" $ do
    (code, _, err) <- stref ["conformance", fixtureCorpus, "--engine", "no-such-engine-stref-test", "--persistent"] ""
    code `shouldBe` ExitFailure 2
    err `shouldSatisfy` ("the engine cannot be started" `isInfixOf`)

  it "refuses --persistent without --engine (exit 2)" $ do
    (code, _, err) <- stref ["conformance", fixtureCorpus, "--persistent"] ""
    code `shouldBe` ExitFailure 2
    err `shouldSatisfy` ("--persistent is for an --engine command" `isInfixOf`)
