-- | The IronPLC adapter. Its logic (what it gives ironplcc, what it
-- declines, the decoding of what the engine printed) is tested on outputs
-- recorded from IronPLC (test/engines/ironplc: each case's @.compile@ is
-- ironplcc's messages when it rejected the case, else @.out@, @.err@ and
-- @.status@ are ironplcvm's output, messages and exit status), so these
-- tests run without the engine. The live tests run the same cases through
-- an installed IronPLC and are skipped without one.
module Engines.IronplcSpec (spec) where

import Control.Monad (forM_)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Case
import Stref.Conformance.Protocol
import Stref.Conformance.Runner (Outcome (..), buildRequest, judgeWith, varComparison)
import qualified Stref.Engines.Ironplc as Ironplc
import Stref.IEC.Types (Elem (..), Type (..))
import Stref.IEC.Values (Value (..))
import Stref.Policy (Policies, ironplc, nexto, tecomat)
import Support.EngineFixture (fixtureCase, liveTests)
import Support.Iec (runUnit)
import System.Directory (doesFileExist)
import System.FilePath ((<.>), (</>))
import Test.Hspec

dir :: FilePath
dir = "test" </> "engines" </> "ironplc"

-- | A recorded case: its request and plan.
load :: String -> IO (Case, Request, Ironplc.Plan)
load name = do
  (c, rq) <- fixtureCase dir name
  pure (c, rq, Ironplc.plan tecomat rq)

loadWith :: Policies -> FilePath -> String -> IO (Case, Request)
loadWith pol file name = do
  src <- TIO.readFile file
  c <- either (fail . T.unpack) pure (parseCase file (CaseOrigin ("tecomat/engine/" <> T.pack name) "tecomat" "engine") (const True) src)
  pure (c, buildRequest pol c (effectiveExpect pol c))

-- | A request for a program written here, under tecomat.
requestFor :: Text -> IO Request
requestFor body = do
  let file = "inline.st"
  c <- either (fail . T.unpack) pure (parseCase file (CaseOrigin "tecomat/engine/inline" "tecomat" "engine") (const True) body)
  pure (buildRequest tecomat c (effectiveExpect tecomat c))

-- | The answer the adapter makes of what IronPLC printed for the case.
recordedAnswer :: String -> IO Answer
recordedAnswer name = do
  (_, _, pl) <- load name
  rejected <- doesFileExist (dir </> name <.> "compile")
  if rejected
    then Ironplc.compileAnswer 1 <$> TIO.readFile (dir </> name <.> "compile")
    else do
      out <- TIO.readFile (dir </> name <.> "out")
      err <- TIO.readFile (dir </> name <.> "err")
      status <- read . T.unpack . T.strip <$> TIO.readFile (dir </> name <.> "status")
      either (fail . T.unpack) pure (Ironplc.runAnswer pl (Ironplc.Finished status out err))

cases :: [String]
cases = ["values", "divide", "mismatch", "not-implemented"]

unsupportedWhy :: Answer -> Text
unsupportedWhy = \case
  AnswerUnsupported why -> why
  other -> "not unsupported: " <> T.pack (show other)

spec :: Spec
spec = describe "the IronPLC adapter" $ do
  describe "what it gives ironplcc" $ do
    it "the case's source unchanged, with the dialect's options: edition 2 with // comments and top-level globals, or CODESYS" $ do
      (_, rq, pl) <- load "values"
      Ironplc.planSource pl `shouldBe` rqSource rq
      Ironplc.planFlags pl `shouldBe` ["--allow-top-level-var-global", "--allow-c-style-comments"]
      Ironplc.planFlags (Ironplc.plan nexto rq) `shouldBe` ["--dialect", "codesys"]
    it "runs as many scans as the case has cycles, observing each path by its name in the dump" $ do
      (_, _, pl) <- load "values"
      case Ironplc.planRun pl of
        Right r -> do
          Ironplc.runScans r `shouldBe` 3
          [(p, n) | (p, n, _) <- Ironplc.runObserved r, p `elem` ["Total", "MAIN.cnt"]] `shouldMatchList` [("Total", "TOTAL"), ("MAIN.cnt", "CNT")]
        Left why -> expectationFailure (T.unpack why)
  describe "what it declines, with the reason (unsupported, after ironplcc accepted the program)" $ do
    let declined body = either id (const "runnable") . Ironplc.planRun . Ironplc.plan tecomat <$> requestFor body
        program decls stmts = "PROGRAM MAIN\nVAR\n" <> decls <> "\nEND_VAR\n" <> stmts <> "\nEND_PROGRAM\n"
        header expect = "(*---\ndescription: inline\nrules: [TC-TYPE-1]\n" <> expect <> "\n---*)\n"
    it "a timer, because ironplcvm keeps the wall clock" $
      declined (header "calls: 2\nexpect:\n  vars: {MAIN.done: false}" <> program "t : TON; done : BOOL;" "t(IN := TRUE, PT := T#1s); done := t.Q;")
        `shouldReturn` "the program reads the clock (TON), and ironplcvm has only the wall clock"
    it "a conversion to TIME is no call of TIME(), which reads the clock" $
      declined (header "expect:\n  vars: {MAIN.d: 5}" <> program "span : TIME; d : DINT := 5;" "span := DINT_TO_TIME(d);")
        `shouldReturn` "runnable"
    it "a variable written between cycles" $
      declined (header "calls:\n  - {set: {MAIN.x: 4}}\nexpect:\n  vars: {MAIN.y: 5}" <> program "x, y : INT;" "y := x + 1;")
        `shouldReturn` "ironplcvm has no way to write a variable between cycles"
    it "a STRING, an array element or an FB's output to observe" $ do
      declined (header "expect:\n  vars: {MAIN.txt: \"'a'\"}" <> program "txt : STRING;" "txt := 'a';")
        >>= (`shouldSatisfy` T.isInfixOf "does not show a value of STRING")
      declined (header "expect:\n  vars:\n    MAIN.a[1]: 2" <> program "a : ARRAY [1..2] OF INT;" "a[1] := 2;")
        >>= (`shouldSatisfy` T.isInfixOf "only the globals and the program's own variables")
      declined (header "expect:\n  vars: {MAIN.edge.Q: true}" <> program "edge : R_TRIG;" "edge(CLK := TRUE);")
        >>= (`shouldSatisfy` T.isInfixOf "only the globals and the program's own variables")
    it "a program and a global of one name, which the dump cannot tell apart" $
      declined ("VAR_GLOBAL x : INT; END_VAR\n" <> header "expect:\n  vars: {MAIN.x: 1}" <> program "x : INT;" "x := 1;")
        >>= (`shouldSatisfy` T.isInfixOf "a global and a program variable alike")
    it "runs a case stref rejects without observing anything, so that an engine that accepts it is seen to" $ do
      (_, rq) <- loadWith tecomat ("conformance" </> "tecomat" </> "rejected" </> "double-underscore-in-fb-name.st") "rejected"
      fmap (\r -> (Ironplc.runObserved r, Ironplc.runScans r)) (Ironplc.planRun (Ironplc.plan tecomat rq)) `shouldSatisfy` \case
        Right ([], _) -> True
        _ -> False
  describe "answers from IronPLC's recorded outputs" $ do
    forM_ cases $ \name ->
      it (name <> ": the adapter's answer meets what the case records of the engine") $ do
        (c, _, _) <- load name
        a <- recordedAnswer name
        let ex = effectiveExpect tecomat c
        case a of
          AnswerUnsupported why -> why `shouldSatisfy` T.isInfixOf "P9999"
          _ -> judgeWith (varComparison tecomat c ex) ex a `shouldBe` Pass
    it "a P9999 is unsupported, with what ironplcc marks as not implemented" $
      recordedAnswer "not-implemented" `shouldReturn` AnswerUnsupported "IronPLC has not implemented this: P9999 Capability is not implemented (yet!): Unsupported array element type"
    it "a rejection gives the case's line and IronPLC's code, without the terminal's colours" $
      recordedAnswer "mismatch" `shouldReturn` AnswerRejected (Just 14) Nothing "P4035: Assignment value type does not match assignment target type (target=b, target_type=bool, value_type=int)"
    it "the dump's values come back exactly: REAL, LREAL, -0, TIME, DATE and DT in seconds, TOD, an enumeration by position" $ do
      a <- recordedAnswer "values"
      case a of
        AnswerRun VerdictOk ob -> do
          M.lookup "MAIN.rr" (obVars ob) `shouldBe` Just (scalarFromFloat 0.1)
          M.lookup "MAIN.neg" (obVars ob) `shouldBe` Just (scalarFromFloat (-0.0))
          M.lookup "MAIN.big" (obVars ob) `shouldBe` Just (SNumber 18446744073709551615)
          M.lookup "MAIN.span" (obVars ob) `shouldBe` Just (SText "T#-1s500ms")
          M.lookup "MAIN.light" (obVars ob) `shouldBe` Just (SText "Light#green")
        other -> expectationFailure ("not ok: " <> show other)
    it "decodes each elementary type as the dump writes it" $ do
      Ironplc.dumpValue (TElem REAL) "100000000000000000000000000000000000000" `shouldBe` Just (VReal 1.0e38)
      Ironplc.dumpValue (TElem LREAL) "-inf" `shouldBe` Just (VLReal (-1 / 0))
      Ironplc.dumpValue (TElem LWORD) "16#000000000000FFFF" `shouldBe` Just (VInt LWORD 65535)
      Ironplc.dumpValue (TElem DATE) "1577923200" `shouldBe` Just (VDate 1577923200000)
      Ironplc.dumpValue (TElem TOD) "43201000" `shouldBe` Just (VTod 43201000)
      Ironplc.dumpValue (TElem TIME) "T#1000ms" `shouldBe` Just (VTime TIME 1000)
      Ironplc.dumpValue (TElem BOOL) "1" `shouldBe` Nothing
    it "a trap: V4001 is division-by-zero, V4005 index-out-of-range; a panic is a crash, a run past the limit the watchdog" $ do
      (_, _, pl) <- load "divide"
      let kindOf = \case
            Right (AnswerRun VerdictRuntimeError ob) -> obError ob >>= erKind
            _ -> Nothing
      kindOf (Ironplc.runAnswer pl (Ironplc.Finished 1 "cnt: 2\nquot: 10\n" "Error: V4001 - runtime error: divide by zero (task 0, instance 0)\n")) `shouldBe` Just "division-by-zero"
      kindOf (Ironplc.runAnswer pl (Ironplc.Finished 1 "" "Error: V4005 - runtime error: array index out of bounds\n")) `shouldBe` Just "index-out-of-range"
      kindOf (Ironplc.runAnswer pl (Ironplc.Finished 101 "" "thread 'main' panicked at vm/src/builtin.rs\n")) `shouldBe` Just "crash"
      kindOf (Ironplc.runAnswer pl Ironplc.TimedOut) `shouldBe` Just "watchdog"
      Ironplc.runAnswer pl (Ironplc.Finished 2 "" "Error: V6001 - Unable to open\n") `shouldSatisfy` either (T.isInfixOf "V6001") (const False)
    it "an unsupported plan answers unsupported whatever the VM printed" $ do
      rq <- requestFor "(*---\ndescription: inline\nrules: [TC-TYPE-1]\nexpect:\n  vars: {MAIN.txt: \"'a'\"}\n---*)\nPROGRAM MAIN\nVAR txt : STRING; END_VAR\ntxt := 'a';\nEND_PROGRAM\n"
      fmap unsupportedWhy (Ironplc.runAnswer (Ironplc.plan tecomat rq) (Ironplc.Finished 0 "s: 0\n" "")) `shouldSatisfy` either (const False) (T.isInfixOf "STRING")
  describe "the engine preset" $
    it "ironplc computes INT arithmetic in 32 bits, truncates REAL to INT, and leaves a subrange unchecked, where tecomat does not" $ do
      let src = "PROGRAM MAIN\nVAR a, b, mean, cut : INT; lvl : INT (0..10); x : REAL := 1.5; END_VAR\na := 20000; b := 20000; mean := (a + b) / 2; cut := REAL_TO_INT(x); lvl := a - 19989;\nEND_PROGRAM\n"
      runUnit ironplc src 1 "MAIN.mean" `shouldBe` Right (VInt INT 20000)
      runUnit tecomat src 1 "MAIN.mean" `shouldBe` Right (VInt INT (-12768))
      runUnit ironplc src 1 "MAIN.cut" `shouldBe` Right (VInt INT 1)
      runUnit ironplc src 1 "MAIN.lvl" `shouldBe` Right (VInt INT 11)
      runUnit tecomat src 1 "MAIN.lvl" `shouldBe` Right (VInt INT 0) -- the store is a subrange error
  liveTests "ironplc" "IronPLC (STREF_IRONPLC or ironplcc on PATH)" cases (fmap (\(_, rq, _) -> rq) . load) recordedAnswer
