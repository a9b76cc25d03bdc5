-- | The skeleton engine of conformance/engines/example (Python, standard
-- library only), run through the built @stref conformance --engine@ against
-- part of the corpus: the cases it passes are exactly those listed, every
-- other case is unsupported, none fails and none is an engine error, also
-- under the other overflow policies (the cases' @expect-if@ entries). Skipped,
-- with a pending message, where python3 is not installed.
module Engines.ExampleSpec (spec) where

import Conformance.Paths (strefBinary)
import Data.Aeson (Value (..), decode)
import qualified Data.Aeson.Key as Key
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy.Char8 as BL
import qualified Data.Text as T
import qualified Data.Vector as V
import System.Directory (findExecutable)
import System.Exit (ExitCode (..))
import System.Process (readProcessWithExitCode)
import Test.Hspec

engine :: String
engine = "python3 conformance/engines/example/engine.py"

-- | The ids that passed, the totals and the exit status of a run of the
-- example engine.
runExample :: [String] -> IO ([String], Value, ExitCode)
runExample = runExampleWith engine

runExampleWith :: String -> [String] -> IO ([String], Value, ExitCode)
runExampleWith command args = do
  bin <- strefBinary
  (code, out, err) <- readProcessWithExitCode bin (["conformance"] ++ args ++ ["--engine", command, "-j", "2", "--format", "json"]) ""
  case decode (BL.pack out) of
    Just (Object report)
      | Just (Array cases) <- KM.lookup "cases" report
      , Just t <- KM.lookup "totals" report -> do
          pure ([T.unpack i | Object c <- V.toList cases, Just (String "pass") <- [KM.lookup "result" c], Just (String i) <- [KM.lookup "id" c]], t, code)
    _ -> expectationFailure ("not a JSON report (exit " ++ show code ++ "): " ++ take 300 out ++ take 300 err) >> fail "no report"

totals :: Int -> Int -> Int -> Value
totals passed unsupported skipped =
  Object (KM.fromList [(Key.fromString k, Number (fromIntegral v)) | (k, v) <- [("passed", passed), ("failed", 0), ("unsupported", unsupported), ("engine-error", 0), ("skipped", skipped)]])

withPython :: IO () -> IO ()
withPython act = findExecutable "python3" >>= maybe (pendingWith "skipped: python3 is not installed, so the example engine cannot run") (const act)

spec :: Spec
spec = describe "the example engine (conformance/engines/example)" $ do
  it "passes exactly its subset of three areas and answers unsupported for every other case, under the dialects' presets" $ withPython $ do
    (passed, t, code) <- runExample ["conformance/tecomat/operators", "conformance/tecomat/programs-cycles", "conformance/nexto/cycles-tasks"]
    passed
      `shouldBe` [ "nexto/cycles-tasks/program-state-kept-between-cycles"
                 , "tecomat/operators/and-xor-or-priorities"
                 , "tecomat/operators/comparison-above-equality"
                 , "tecomat/operators/dint-multiplication-overflow"
                 , "tecomat/operators/equality-chain-ending-in-bool"
                 , "tecomat/operators/int-addition-overflow"
                 , "tecomat/programs-cycles/first-cycle-initialisation"
                 ]
    t `shouldBe` totals 7 49 0
    code `shouldBe` ExitSuccess

  it "gives the same results in persistent mode (engine.py --persistent, stref conformance --persistent)" $ withPython $ do
    let paths = ["conformance/tecomat/operators", "conformance/tecomat/programs-cycles", "conformance/nexto/cycles-tasks"]
    (alone, t, _) <- runExample paths
    (persistent, t', code) <- runExampleWith (engine ++ " --persistent") (paths ++ ["--persistent"])
    persistent `shouldBe` alone
    t' `shouldBe` t
    code `shouldBe` ExitSuccess

  -- the same two overflow cases pass under each alternative: the engine
  -- follows the request's policy (wrap -25536, saturate 32767, trap: the
  -- runtime error overflow at the addition's line), and the runner judges
  -- each by its expect-if entry
  it "follows the overflow policy of the request: wrap, saturate and trap" $ withPython $
    mapM_
      ( \choice -> do
          (passed, t, code) <- runExample ["conformance/tecomat/operators", "--filter", "*overflow*", "--policy", "overflow=" ++ choice]
          passed `shouldBe` ["tecomat/operators/dint-multiplication-overflow", "tecomat/operators/int-addition-overflow"]
          t `shouldBe` totals 2 2 33 -- the cases outside the filter are skipped
          code `shouldBe` ExitSuccess
      )
      ["wrap", "saturate", "trap"]

  -- the engine's features file makes the cases it lacks unsupported without
  -- a call (the runner's reason names the feature) and loses no pass
  it "keeps its passes when its features file (lacking-features.txt) declares what it lacks" $ withPython $ do
    let paths = ["conformance/tecomat/operators", "conformance/tecomat/programs-cycles", "conformance/nexto/cycles-tasks"]
    (alone, t, _) <- runExample paths
    (declared, t', code) <- runExample (paths ++ ["--features-file", "conformance/engines/example/lacking-features.txt"])
    declared `shouldBe` alone
    t' `shouldBe` t
    code `shouldBe` ExitSuccess

  -- generated programs use every type and statement of the IEC core: the
  -- engine declines them all, unless explore leaves out what it lacks
  describe "under stref explore --dialect tecomat --engine" $ do
    let explore extra = do
          bin <- strefBinary
          readProcessWithExitCode bin (["explore", "--dialect", "tecomat", "--engine", engine, "--count", "15", "--seed", "3"] ++ extra) ""
    it "declines every generated program when nothing is left out" $ withPython $ do
      (code, out, _) <- explore []
      out `shouldContain` "no disagreement in 15 programs (15 rejected or declined by the engine)"
      code `shouldBe` ExitSuccess
    it "runs and agrees on every program made of what it implements (--features-file)" $ withPython $ do
      (code, out, _) <- explore ["--features-file", "conformance/engines/example/lacking-features.txt"]
      out `shouldContain` "the programs use only types BOOL, INT, DINT; statements assignment, IF; functions none"
      lines out `shouldContain` ["no disagreement in 15 programs"]
      code `shouldBe` ExitSuccess
