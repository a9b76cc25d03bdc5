-- | The MATIEC adapter. Its logic (the program given to iec2c, the driver,
-- the decoding of what the engine printed) is tested on outputs recorded
-- from MATIEC (test/engines/matiec: each case's @.out@ is the driver's
-- output, @.err@ iec2c's messages, @.located@ its LOCATED_VARIABLES.h), so
-- these tests run without the engine. The live tests run the same cases
-- through an installed MATIEC and are skipped without one.
module Engines.MatiecSpec (spec) where

import Control.Monad (forM_)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Case
import Stref.Conformance.Protocol
import Stref.Conformance.Runner (Outcome (..), judgeWith, varComparison)
import qualified Stref.Engines.Matiec as Matiec
import Stref.IEC.Types (Elem (..))
import Stref.IEC.Values (Value (..))
import Stref.Policy (matiec, openplc, tecomat)
import Support.EngineFixture (fixtureCase, liveTests)
import Support.Iec (runUnit)
import System.Directory (doesFileExist)
import System.FilePath ((<.>), (</>))
import Test.Hspec

dir :: FilePath
dir = "test" </> "engines" </> "matiec"

-- | A recorded case: its request and plan.
load :: String -> IO (Case, Request, Matiec.Plan)
load name = do
  (c, rq) <- fixtureCase dir name
  pl <- either (fail . T.unpack) pure (Matiec.plan tecomat rq)
  pure (c, rq, pl)

-- | The answer the adapter makes of what MATIEC printed for the case.
recordedAnswer :: String -> IO Answer
recordedAnswer name = do
  (_, _, pl) <- load name
  hasErr <- doesFileExist (dir </> name <.> "err")
  if hasErr
    then Matiec.compileAnswer 1 <$> TIO.readFile (dir </> name <.> "err")
    else do
      located <- Matiec.locatedNames <$> TIO.readFile (dir </> name <.> "located")
      either (fail . T.unpack) (const (pure ())) (Matiec.driverSource pl located)
      Matiec.runAnswer pl . Matiec.Finished <$> TIO.readFile (dir </> name <.> "out")

cases :: [String]
cases = ["values", "divide", "endless", "for-once", "undeclared"]

spec :: Spec
spec = describe "the MATIEC adapter" $ do
  describe "the program iec2c compiles" $ do
    it "moves the top-level globals into a CONFIGURATION with one task at the case's cycle, keeping every line" $ do
      (_, rq, pl) <- load "values"
      let src = Matiec.planSource pl
          original = T.lines (rqSource rq)
      -- the case's lines keep their numbers: the wrapper comes after them
      length (T.lines src) `shouldSatisfy` (> length original)
      T.lines src !! 21 `shouldBe` T.replicate (T.length (original !! 21)) " "
      src `shouldSatisfy` T.isInfixOf "CONFIGURATION StrefConfig"
      src `shouldSatisfy` T.isInfixOf "TASK StrefTask(INTERVAL := T#10ms, PRIORITY := 0);"
      src `shouldSatisfy` T.isInfixOf "PROGRAM StrefMain WITH StrefTask : MAIN;"
    it "declares the globals VAR_EXTERNAL on the line of the POU's header" $ do
      (_, _, pl) <- load "values"
      [l | l <- T.lines (Matiec.planSource pl), "PROGRAM MAIN" `T.isPrefixOf` l] `shouldBe` ["PROGRAM MAIN VAR_EXTERNAL total : DINT; END_VAR "]
  describe "the driver" $ do
    it "reads a program's variables, an FB's, array elements, structure fields, globals and direct addresses" $ do
      (_, _, pl) <- load "values"
      located <- Matiec.locatedNames <$> TIO.readFile (dir </> "values.located")
      located `shouldBe` [("__QW1", "WORD")]
      driver <- either (fail . T.unpack) pure (Matiec.driverSource pl located)
      forM_
        [ "STREFRESOURCE__STREFMAIN.T.Q.value"
        , "STREFRESOURCE__STREFMAIN.T.ET.value"
        , "STREFRESOURCE__STREFMAIN.PTS.value.table[1].X"
        , "(*__GET_GLOBAL_TOTAL())"
        , "(*__QW1)"
        , "put_real(STREFRESOURCE__STREFMAIN.RR.value)"
        , "put_string(STREFRESOURCE__STREFMAIN.TXT.value)"
        , "STREFRESOURCE__STREFMAIN.SPEED.value = ((long long)-7LL);"
        ]
        $ \needle -> driver `shouldSatisfy` T.isInfixOf needle
    it "writes a cycle's variables before that cycle only" $ do
      (_, _, pl) <- load "values"
      driver <- either (fail . T.unpack) pure (Matiec.driverSource pl [("__QW1", "WORD")])
      let cases2 = takeWhile (/= "  default: break;") (dropWhile (/= "  case 2:") (T.lines driver))
      cases2 `shouldBe` ["  case 2:", "    STREFRESOURCE__STREFMAIN.SPEED.value = ((long long)-7LL);", "    STREFRESOURCE__STREFMAIN.START.value = 1;", "    break;"]
    it "says unsupported for a reset, which it cannot give the engine" $ do
      (_, rq, _) <- load "values"
      let reset = rq {rqCalls = rqCalls rq ++ [CallRequest (True, True, True) M.empty (Just "warm")]}
      either id (const "") (Matiec.plan tecomat reset) `shouldSatisfy` T.isInfixOf "reset"
    it "cannot observe a direct address the program does not declare" $ do
      (_, _, pl) <- load "values"
      Matiec.driverSource pl [] `shouldSatisfy` either (T.isInfixOf "%QW1") (const False)
  describe "answers from MATIEC's recorded outputs" $ do
    forM_ cases $ \name ->
      it (name <> ": the adapter's answer meets what the case records of the engine") $ do
        (c, _, _) <- load name
        a <- recordedAnswer name
        let ex = effectiveExpect tecomat c
        judgeWith (varComparison tecomat c ex) ex a `shouldBe` Pass
    it "values come back exactly: REAL by its bits, LREAL, TIME, DATE, TOD, STRING bytes, an array of structures" $ do
      a <- recordedAnswer "values"
      case a of
        AnswerRun VerdictOk ob -> do
          M.lookup "MAIN.rr" (obVars ob) `shouldBe` Just (scalarFromFloat 0.1)
          M.lookup "MAIN.txt" (obVars ob) `shouldBe` Just (SText "'ab$'c'")
          M.lookup "MAIN.t.ET" (obVars ob) `shouldBe` Just (SText "T#30ms")
          M.lookup "MAIN.big" (obVars ob) `shouldBe` Just (SNumber (-9000000000))
          M.lookup "%QW1" (obVars ob) `shouldBe` Just (SNumber 6)
        other -> expectationFailure ("not ok: " <> show other)
    it "a trap by SIGFPE is division-by-zero, SIGALRM the watchdog, output without its end a crash" $ do
      (_, _, pl) <- load "divide"
      errKind (Matiec.runAnswer pl (Matiec.Finished "trap 8 2\nend\n")) `shouldBe` Just "division-by-zero"
      errKind (Matiec.runAnswer pl (Matiec.Finished "trap 14 1\nend\n")) `shouldBe` Just "watchdog"
      errKind (Matiec.runAnswer pl (Matiec.Finished "trap 11 3\n")) `shouldBe` Just "crash"
      errKind (Matiec.runAnswer pl Matiec.TimedOut) `shouldBe` Just "watchdog"
    it "iec2c's messages: the line of the case's file, not of the engine's library; a crash of iec2c" $ do
      Matiec.compileAnswer 1 "case.st:9-6..9-12: error: Data type mismatch for '+' expression.\n1 error(s) found. Bailing out!\n"
        `shouldBe` AnswerRejected (Just 9) Nothing "Data type mismatch for '+' expression."
      Matiec.compileAnswer 1 "/x/case.st:5: error: ';' missing at the end of statement in ST statement.\n"
        `shouldBe` AnswerRejected (Just 5) Nothing "';' missing at the end of statement in ST statement."
      Matiec.compileAnswer 1 "timer.txt:80: error: invalid input variable(s) declaration.\n" `shouldSatisfy` \case
        AnswerRejected Nothing _ m -> "timer.txt" `T.isInfixOf` m
        _ -> False
      Matiec.compileAnswer (-11) "" `shouldSatisfy` \case
        AnswerRejected Nothing _ m -> "crashed" `T.isInfixOf` m
        _ -> False
  describe "the engine presets" $
    it "matiec's F_TRIG gives an edge in the first cycle, openplc's does not; both hold 126 characters in a STRING" $ do
      let src = "PROGRAM MAIN\nVAR f : F_TRIG; falls : INT; txt : STRING; idx : INT; END_VAR\nf(CLK := FALSE); IF f.Q THEN falls := falls + 1; END_IF;\ntxt := 'x'; FOR idx := 1 TO 200 DO txt := CONCAT(txt, 'x'); END_FOR;\nEND_PROGRAM\n"
      runUnit matiec src 3 "MAIN.falls" `shouldBe` Right (VInt INT 1)
      runUnit openplc src 3 "MAIN.falls" `shouldBe` Right (VInt INT 0)
      fmap (\case VString t -> T.length t; _ -> 0) (runUnit matiec src 1 "MAIN.txt") `shouldBe` Right 126
  liveTests "matiec" "MATIEC (STREF_MATIEC or iec2c on PATH)" cases (fmap (\(_, rq, _) -> rq) . load) recordedAnswer
  where
    errKind :: Answer -> Maybe Text
    errKind = \case
      AnswerRun _ ob -> obError ob >>= erKind
      _ -> Nothing
