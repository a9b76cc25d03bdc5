-- | The RuSTy adapter. Its logic (the probes, the driver, what it declines,
-- the decoding of what the driver printed and of plc's messages) is tested
-- on outputs recorded from RuSTy (test/engines/rusty: each case, the
-- driver's output @.out@, or plc's messages @.compile@), so these tests run
-- without the engine. The live tests run the same cases through an
-- installed RuSTy and are skipped without one.
module Engines.RustySpec (spec) where

import Control.Monad (forM_)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Case
import Stref.Conformance.Protocol
import Stref.Conformance.Runner (Outcome (..), buildRequest, judgeWith, varComparison)
import qualified Stref.Engines.Rusty as Rusty
import Stref.IEC.Values (Value (..))
import Stref.Policy (rusty, tecomat)
import Support.EngineFixture (fixtureCase, liveTests)
import Support.Iec (runUnit)
import System.Directory (doesFileExist)
import System.FilePath ((<.>), (</>))
import Test.Hspec

dir :: FilePath
dir = "test" </> "engines" </> "rusty"

load :: String -> IO (Case, Request, Rusty.Plan)
load name = do
  (c, rq) <- fixtureCase dir name
  pl <- either (fail . T.unpack) pure (Rusty.plan tecomat rq)
  pure (c, rq, pl)

runOf :: Rusty.Plan -> IO Rusty.Run
runOf = either (fail . T.unpack) pure . Rusty.planRun

-- | The answer the adapter makes of what RuSTy printed for the case.
recordedAnswer :: String -> IO Answer
recordedAnswer name = do
  (_, _, pl) <- load name
  rejected <- doesFileExist (dir </> name <.> "compile")
  if rejected
    then Rusty.compileAnswer 1 <$> TIO.readFile (dir </> name <.> "compile")
    else do
      r <- runOf pl
      Rusty.runAnswer r . Rusty.Finished <$> TIO.readFile (dir </> name <.> "out")

cases :: [String]
cases = ["values", "divide", "mismatch"]

inline :: Text -> IO Request
inline body = do
  c <- either (fail . T.unpack) pure (parseCase "inline.st" (CaseOrigin "tecomat/engine/inline" "tecomat" "engine") (const True) body)
  pure (buildRequest tecomat c (effectiveExpect tecomat c))

spec :: Spec
spec = describe "the RuSTy adapter" $ do
  describe "what it gives plc and the C compiler" $ do
    it "the case unchanged, and a probe per path that gives the variable's address" $ do
      (_, rq, pl) <- load "values"
      Rusty.planSource pl `shouldBe` rqSource rq
      T.lines (Rusty.planProbes pl) `shouldSatisfy` any (T.isInfixOf ": LWORD __stref_p" <&&> T.isInfixOf ":= ADR(MAIN.t.ET); END_FUNCTION")
      T.lines (Rusty.planProbes pl) `shouldSatisfy` any (T.isInfixOf "ADR(Total)")
    it "a driver whose clock_gettime is the virtual clock, (k - 1) x the cycle in cycle k, and which writes a cycle's inputs before it" $ do
      (_, _, pl) <- load "values"
      r <- runOf pl
      let c = Rusty.driverSource r
      c `shouldSatisfy` T.isInfixOf "int clock_gettime(clockid_t id, struct timespec *ts)"
      c `shouldSatisfy` T.isInfixOf "virtual_ns = (int64_t)(k - 1) * 10000000LL;"
      c `shouldSatisfy` T.isInfixOf "MAIN(MAIN_instance);"
      [l | l <- T.lines c, "    *AT(" `T.isPrefixOf` l, "int16_t" `T.isInfixOf` l] `shouldSatisfy` any (T.isInfixOf "= (int16_t)(-7LL);")
      c `shouldSatisfy` T.isInfixOf "for (int j = 0; j < 3; j++)"
    it "declines a CONFIGURATION and a reset before compiling, a direct address after" $ do
      let header = "(*---\ndescription: inline\nrules: [TC-TYPE-1]\nexpect:\n  vars: {MAIN.x: 1}\n---*)\n"
      cfg <- inline (header <> "PROGRAM P1\nVAR x : INT; END_VAR\nx := 1;\nEND_PROGRAM\nCONFIGURATION C\nRESOURCE R ON PLC\nTASK T(INTERVAL := T#10ms, PRIORITY := 1);\nPROGRAM MAIN WITH T : P1;\nEND_RESOURCE\nEND_CONFIGURATION\n")
      either id (const "") (() <$ Rusty.plan tecomat cfg) `shouldSatisfy` T.isInfixOf "CONFIGURATION"
      plain <- inline (header <> "PROGRAM MAIN\nVAR x : INT; END_VAR\nx := 1;\nEND_PROGRAM\n")
      let reset = plain {rqCalls = rqCalls plain ++ [CallRequest (True, True, True) M.empty (Just "warm")]}
      either id (const "") (() <$ Rusty.plan tecomat reset) `shouldSatisfy` T.isInfixOf "reset"
      let located = plain {rqObserve = (rqObserve plain) {obsOperands = ["%QX0.0"]}}
      fmap (either id (const "") . Rusty.planRun) (Rusty.plan tecomat located) `shouldSatisfy` either (const False) (T.isInfixOf "direct addresses")
  describe "answers from RuSTy's recorded outputs" $ do
    forM_ cases $ \name ->
      it (name <> ": the adapter's answer meets what the case records of the engine") $ do
        (c, _, _) <- load name
        a <- recordedAnswer name
        let ex = effectiveExpect tecomat c
        judgeWith (varComparison tecomat c ex) ex a `shouldBe` Pass
    it "values come back exactly: REAL and LREAL by their bits, TIME in nanoseconds, a STRING's bytes, an array, an enumeration" $ do
      a <- recordedAnswer "values"
      case a of
        AnswerRun VerdictOk ob -> do
          M.lookup "MAIN.rr" (obVars ob) `shouldBe` Just (scalarFromFloat 0.1)
          M.lookup "MAIN.label" (obVars ob) `shouldBe` Just (SText "'go!'")
          M.lookup "MAIN.t.ET" (obVars ob) `shouldBe` Just (SText "T#30ms")
          M.lookup "MAIN.arr" (obVars ob) `shouldBe` Just (SList [SNumber 1, SNumber 2, SNumber 4])
          M.lookup "MAIN.light" (obVars ob) `shouldBe` Just (SText "Light#green")
        other -> expectationFailure ("not ok: " <> show other)
    it "a trap: SIGFPE is division-by-zero, SIGALRM the watchdog, SIGABRT (a panic in RuSTy's library) a crash" $ do
      (_, _, pl) <- load "divide"
      r <- runOf pl
      let kindOf = \case
            AnswerRun VerdictRuntimeError ob -> obError ob >>= erKind
            _ -> Nothing
      kindOf (Rusty.runAnswer r (Rusty.Finished "trap 8 2\n= 2\n= 10\nend\n")) `shouldBe` Just "division-by-zero"
      kindOf (Rusty.runAnswer r (Rusty.Finished "trap 14 1\nend\n")) `shouldBe` Just "watchdog"
      kindOf (Rusty.runAnswer r (Rusty.Finished "trap 6 1\nend\n")) `shouldBe` Just "crash"
      kindOf (Rusty.runAnswer r (Rusty.Finished "= 1\n")) `shouldBe` Just "crash"
      kindOf (Rusty.runAnswer r Rusty.TimedOut) `shouldBe` Just "watchdog"
    it "plc's messages: an error's line in the case; a line counted from 0 in its 'at:' form; an error in the probes is unsupported" $ do
      Rusty.compileAnswer 1 "/tmp/x/case.st:5:14:{5:14-5:15}: error[E007]: Unexpected token: expected Literal but found ;\nCompilation aborted due to critical parse errors.\n"
        `shouldBe` AnswerRejected (Just 5) Nothing "Unexpected token: expected Literal but found ;"
      Rusty.compileAnswer 1 "Cannot break out of loop when not inside a loop at: /tmp/x/case.st:14:2:{14:2-14:6}: \n"
        `shouldBe` AnswerRejected (Just 15) Nothing "Cannot break out of loop when not inside a loop"
      Rusty.compileAnswer 1 "/tmp/x/stref_probes.st:1:52:{1:52-1:60}: error[E048]: Could not resolve reference to nothing\n" `shouldSatisfy` \case
        AnswerUnsupported m -> "Could not resolve" `T.isInfixOf` m
        _ -> False
  describe "the engine preset" $
    it "rusty's TON gives Q a cycle after ET reaches PT, and its STRING holds 80 characters, where tecomat's does not" $ do
      let src = "PROGRAM MAIN\nVAR t : TON; done : BOOL; txt : STRING; i : INT; END_VAR\nt(IN := TRUE, PT := T#30ms); done := t.Q;\ntxt := ''; FOR i := 1 TO 100 DO txt := CONCAT(txt, 'x'); END_FOR;\nEND_PROGRAM\n"
      runUnit rusty src 4 "MAIN.done" `shouldBe` Right (VBool False)
      runUnit rusty src 5 "MAIN.done" `shouldBe` Right (VBool True)
      runUnit tecomat src 4 "MAIN.done" `shouldBe` Right (VBool True)
      fmap (\case VString t -> T.length t; _ -> 0) (runUnit rusty src 1 "MAIN.txt") `shouldBe` Right 80
  liveTests "rusty" "RuSTy (STREF_RUSTY or plc on PATH)" cases (fmap (\(_, rq, _) -> rq) . load) recordedAnswer
  where
    (<&&>) f g x = f x && g x
