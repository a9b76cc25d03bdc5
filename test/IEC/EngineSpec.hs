-- | The IEC core from source text to observed values: the parser's
-- priorities and literals, the checker's reject kinds, cycles on the
-- virtual clock, the after-error policy, variable paths and the typed
-- comparison of answers. Expected values come from the rules named, worked
-- out by hand.
module IEC.EngineSpec (spec) where

import Data.Either (isLeft)
import qualified Data.Text as T
import qualified Data.Map.Strict as M
import Stref.Conformance.Protocol
import Stref.Engine (referenceEngine)
import Stref.IEC.Engine
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Support.Iec
import Test.Hspec

spec :: Spec
spec = describe "IEC.Engine" $ do
  describe "expressions (Tab.3.23)" $ do
    it "** binds tighter than unary minus: -x**2 with x = 2 is -4 (TC-OP-1)" $
      runMain tecomat "VAR x : INT := 2; y : INT; END_VAR y := -x**2;" 1 "y" `shouldBe` Right (VInt INT (-4))
    it "** is left-associative: 2**3**2 = 64 (TC-OP-4)" $
      runMain tecomat "VAR y : DINT; END_VAR y := 2**3**2;" 1 "y" `shouldBe` Right (VInt DINT 64)
    it "AND binds tighter than XOR, XOR tighter than OR (TC-OP-1)" $
      runMain tecomat "VAR b : BOOL; END_VAR b := TRUE OR TRUE XOR TRUE AND FALSE;" 1 "b" `shouldBe` Right (VBool True)
    it "an untyped literal takes its context's type: SINT 127 + 1 wraps under the preset (TC-CONV-4, TC-OP-20)" $
      runMain tecomat "VAR sv : SINT := 127; END_VAR sv := sv + 1;" 1 "sv" `shouldBe` Right (VInt SINT (-128))
    it "and saturates under overflow=saturate" $
      runMain tecomat {pOverflow = Saturate} "VAR sv : SINT := 127; END_VAR sv := sv + 1;" 1 "sv" `shouldBe` Right (VInt SINT 127)
  describe "the checker" $ do
    it "rejects INT assigned to DINT under implicit-conversions=none, at the line of the value (TC-CONV-3)" $
      rejectKind tecomat "PROGRAM MAIN\nVAR i : INT; d : DINT; END_VAR\nd := i;\nEND_PROGRAM\n" `shouldBe` Just ("type-mismatch", 3)
    it "accepts it under iec-widening" $
      rejectKind tecomat {pImplicitConversions = ImplicitIecWidening} "PROGRAM MAIN\nVAR i : INT; d : DINT; END_VAR\nd := i;\nEND_PROGRAM\n" `shouldBe` Nothing
    it "rejects writing a VAR_INPUT inside its FB (TC-VAR-1)" $
      rejectKind tecomat "FUNCTION_BLOCK F\nVAR_INPUT a : INT; END_VAR\na := 1;\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nEND_PROGRAM\n" `shouldBe` Just ("write-not-allowed", 3)
    it "rejects a standard FB's name as a variable name (TC-LEX-3)" $
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR TON : INT; END_VAR\nEND_PROGRAM\n") `shouldBe` Just "reserved-name"
    it "rejects a national letter in a name with invalid-identifier (TC-LEX-12)" $
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR \x158\&ek : INT; END_VAR\nEND_PROGRAM\n") `shouldBe` Just "invalid-identifier"
    it "rejects mutual recursion (TC-POU-2)" $
      fmap fst (rejectKind tecomat "FUNCTION A : INT\nVAR_INPUT x : INT; END_VAR\nA := B(x);\nEND_FUNCTION\nFUNCTION B : INT\nVAR_INPUT x : INT; END_VAR\nB := A(x);\nEND_FUNCTION\nPROGRAM MAIN\nEND_PROGRAM\n") `shouldBe` Just "recursive-call"
  describe "robustness (docs/robustness.md)" $ do
    let deep = 10000
        prog body = "PROGRAM MAIN\nVAR x : DINT; b : BOOL; END_VAR\n" <> body <> "\nEND_PROGRAM\n"
    it "10,000 nested parentheses are refused with nesting-too-deep" $
      fmap fst (rejectKind tecomat (prog ("x := " <> T.replicate deep "(" <> "1" <> T.replicate deep ")" <> ";"))) `shouldBe` Just "nesting-too-deep"
    it "10,000 nested IFs are refused with nesting-too-deep" $
      fmap fst (rejectKind tecomat (prog (T.replicate deep "IF TRUE THEN " <> "x := 1;" <> T.replicate deep " END_IF;"))) `shouldBe` Just "nesting-too-deep"
    it "10,000 NOTs are refused with nesting-too-deep" $
      fmap fst (rejectKind tecomat (prog ("b := " <> T.replicate deep "NOT " <> "TRUE;"))) `shouldBe` Just "nesting-too-deep"
    it "a sum of 10,000 ones is computed (no depth limit on a left-associative chain)" $
      runMain tecomat ("VAR x : DINT; END_VAR x := " <> T.intercalate " + " (replicate deep "1") <> ";") 1 "x" `shouldBe` Right (VInt DINT 10000)
    it "200 nested parentheses are accepted" $
      runMain tecomat ("VAR x : DINT; END_VAR x := " <> T.replicate 199 "(" <> "7" <> T.replicate 199 ")" <> ";") 1 "x" `shouldBe` Right (VInt DINT 7)
  describe "cycles and the clock (corpus-format 4.1)" $ do
    it "a program's variables keep their values from cycle to cycle (TC-POU-15)" $
      runMain tecomat "VAR cnt : INT; END_VAR cnt := cnt + 1;" 5 "cnt" `shouldBe` Right (VInt INT 5)
    it "VAR_TEMP starts afresh in every cycle (TC-VAR-8)" $
      runMain tecomat "VAR_TEMP t : INT; END_VAR VAR cnt : INT; END_VAR t := t + 1; cnt := t;" 3 "cnt" `shouldBe` Right (VInt INT 1)
    it "TON's Q rises in cycle 6 of 10 ms for PT = 50 ms: the clock reads (k-1) x cycle (TC-FB-27)" $ do
      let body = "VAR t : TON; cnt : INT; first : INT; END_VAR cnt := cnt + 1; t(IN := TRUE, PT := T#50ms); IF t.Q AND first = 0 THEN first := cnt; END_IF;"
      runMain tecomat body 8 "first" `shouldBe` Right (VInt INT 6)
      runMain tecomat {pTimerQ = NextCycle} body 8 "first" `shouldBe` Right (VInt INT 7)
    it "F_TRIG gives no edge on a first FALSE under Tecomat's M := TRUE, and one under the IEC reading (TC-FB-15)" $ do
      let body = "VAR f : F_TRIG; qq : BOOL; END_VAR f(CLK := FALSE); qq := f.Q;"
      runMain tecomat body 1 "qq" `shouldBe` Right (VBool False)
      runMain tecomat {pFTrigInitial = FTrigFalse} body 1 "qq" `shouldBe` Right (VBool True)
  describe "runtime errors (corpus-format 4.3)" $ do
    it "an endless WHILE ends the cycle with watchdog (TC-STMT-34)" $
      errorOf tecomat {pStepBudget = 1000} "VAR b : BOOL := TRUE; END_VAR WHILE b DO b := TRUE; END_WHILE;" 1 `shouldBe` Just (1, "watchdog")
    it "after-error=stop: later cycles do not run" $
      runMain tecomat "VAR cnt : INT; z : INT; END_VAR cnt := cnt + 1; IF cnt = 2 THEN cnt := cnt / z; END_IF;" 4 "cnt" `shouldBe` Right (VInt INT 2)
    it "after-error=continue: they do, and the first error is the one reported" $ do
      let body = "VAR cnt : INT; z : INT; END_VAR cnt := cnt + 1; IF cnt = 2 THEN cnt := cnt / z; END_IF;"
      runMain tecomat {pAfterError = ContinueNextCycle} body 4 "cnt" `shouldBe` Right (VInt INT 4)
      errorOf tecomat {pAfterError = ContinueNextCycle} body 4 `shouldBe` Just (2, "division-by-zero")
    it "an index outside the bounds is index-out-of-range, or clamped (TC-ERR-3)" $ do
      let body = "VAR a : ARRAY [1..3] OF INT; i : INT := 4; END_VAR a[i] := 7;"
      errorOf tecomat body 1 `shouldBe` Just (1, "index-out-of-range")
      runMain tecomat {pIndexOutOfRange = IndexClamp} body 1 "a[3]" `shouldBe` Right (VInt INT 7)
  describe "values of the protocol (corpus-format 4.2)" $ do
    it "compares times by value: T#95s equals T#1m35s" $
      scalarsMatch tecomat (TElem TIME) (SText "T#95s") (SText "T#1m35s") `shouldBe` True
    it "compares REAL as binary32: 0.1 matches the binary32 nearest to 0.1 written in full" $
      scalarsMatch tecomat (TElem REAL) (SNumber 0.1) (SNumber 0.100000001490116119384765625) `shouldBe` True
    it "compares LREAL as binary64: the same two differ" $
      scalarsMatch tecomat (TElem LREAL) (SNumber 0.1) (SNumber 0.100000001490116119384765625) `shouldBe` False
    it "reads a bit string's negative number as its pattern: -1 is WORD 16#FFFF" $
      scalarsMatch tecomat (TElem WORD) (SNumber (-1)) (SNumber 65535) `shouldBe` True
    it "rejects a path that is not a variable path" $
      parseVarPath "MAIN..x" `shouldSatisfy` isLeft
    it "parses nested paths with indices" $
      parseVarPath "MAIN.a[2, 3].f" `shouldBe` Right [StepField "MAIN", StepField "A", StepIndex [2, 3], StepField "F"]
    it "renders values as ST literals" $
      map renderValue [VTime TIME 95000, VTod 23599999, VDate (12 * msPerDay), VString "a'b"] `shouldBe` ["T#1m35s", "TOD#06:33:19.999", "D#1970-01-13", "'a$'b'"]
    it "the IEC engine answers lifetime=per-call with unsupported: its state persists (TC-POU-15)" $ do
      let rq = Request "stref-engine/1" "t" "tecomat" (M.fromList [("lifetime", "per-call")]) "PROGRAM MAIN\nEND_PROGRAM\n" "P" (PlcRequest (Declare M.empty M.empty) "" M.empty Nothing) [CallRequest (True, True, True) M.empty Nothing] (Observe [] [] [] True) Nothing Nothing
      case referenceEngine [] rq of
        AnswerUnsupported why -> why `shouldSatisfy` T.isInfixOf "per-call"
        other -> expectationFailure (show other)
    it "the cycle must be a positive TIME" $
      cycleMillis tecomat "T#0ms" `shouldSatisfy` isLeft
