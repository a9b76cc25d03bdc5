-- | The whole pipeline on ST source: parse, check, run (Stref.Run).
module ExecutionSourceSpec (spec) where

import Data.Text (Text)
import qualified Data.Text as T
import Stref.Checked (ModuleKind (..))
import Stref.Diagnostics
import Stref.Execution
import Stref.Operands
import Stref.Policy
import Stref.Run
import Stref.Values
import Test.Hspec

src :: [Text] -> Text
src = T.unlines

runWith :: Policies -> ModuleKind -> [(Operand, Setting)] -> [CallSpec] -> Text -> Either RunFailure RunOutcome
runWith p kind inits calls text = runSource (RunSetup p defaultPlcConfig kind inits) "test.st" text calls

runP :: Policies -> Int -> Text -> Either RunFailure RunOutcome
runP p n = runWith p ProcedureModule [] (replicate n defaultCallSpec)

lastResult :: RunOutcome -> Maybe CallResult
lastResult o = case roResults o of
  [] -> Nothing
  rs -> Just (last rs)

var :: Text -> RunOutcome -> Maybe Value
var n o = lastResult o >>= lookup n . crVars

errorOf :: RunOutcome -> Maybe RuntimeError
errorOf o = lastResult o >>= crError

operand :: Text -> RunOutcome -> Maybe Value
operand t o = either (const Nothing) (Just . observeOperand (psMemory (roFinal o))) (parseOperand t)

band :: RunOutcome -> [Maybe Value]
band o = [Just (observeOperand (psMemory (roFinal o)) b) | b <- diagnosticBand defaultPlcConfig]

spec :: Spec
spec = describe "Execution from source" $ do
  describe "saturation example of the corpus format (MT-OP-6, MT-OP-7)" $ do
    let program =
          src
            [ "VAR"
            , "  A AT %M0010 : INT;"
            , "  B AT %M0011 : INT;"
            , "  R AT %M0012 : INT;"
            , "  OV AT %M0013.0 : BOOL;"
            , "END_VAR"
            , "PROGRAM SAT"
            , "R := A + B;"
            , "OV := INTERNAL_OVERFLOW;"
            , "END_PROGRAM"
            ]
        inits = [(OpSimple KM 10, SetInt 15000), (OpSimple KM 11, SetInt 25000)]
        r = runWith mastertoolXE ProcedureModule inits [defaultCallSpec] program
    -- 15000 + 25000 = 40000 > 32767: saturates, flag TRUE
    it "stores 32767 and sets the flag bit" $
      fmap (\o -> (operand "%M0012" o, operand "%M0013.0" o)) r `shouldBe` Right (Just (VInt 32767), Just (VBool True))
    it "wraps under overflow = wrap: 40000 - 65536 = -25536" $
      fmap (operand "%M0012") (runWith mastertoolXE {pOverflow = Wrap} ProcedureModule inits [defaultCallSpec] program) `shouldBe` Right (Just (VInt (-25536)))

  describe "name resolution (MT-SCOPE-5, A4)" $ do
    let program = src ["VAR", "  G : INT := 1;", "END_VAR", "PROGRAM P", "VAR", "  G : INT := 5;", "  R : INT;", "END_VAR", "R := G;", "G := 7;", "END_PROGRAM"]
    it "global-wins: the program's G is the global one" $
      fmap (\o -> (var "P.R" o, var "G" o)) (runP mastertoolXE 1 program) `shouldBe` Right (Just (VInt 1), Just (VInt 7))
    it "local-wins: the program's G is its own" $
      fmap (\o -> (var "P.R" o, var "G" o)) (runP mastertoolXE {pNameResolution = LocalWins} 1 program) `shouldBe` Right (Just (VInt 5), Just (VInt 1))

  describe "lifetime across two calls (MT-SCOPE-7)" $ do
    let program = src ["VAR", "  N : INT;", "END_VAR", "PROGRAM P", "VAR", "  L : INT := 10;", "END_VAR", "N := N + 1;", "L := L + 1;", "END_PROGRAM"]
    it "per-call: N = 1 and L = 11 after the second call" $
      fmap (\o -> (var "N" o, var "P.L" o)) (runP mastertoolXE 2 program) `shouldBe` Right (Just (VInt 1), Just (VInt 11))
    it "retained: N = 2 and L = 12 after the second call" $
      fmap (\o -> (var "N" o, var "P.L" o)) (runP mastertoolXE {pLifetime = Retained} 2 program) `shouldBe` Right (Just (VInt 2), Just (VInt 12))

  describe "nesting depth from source (MT-POU-9)" $ do
    -- F<k> calls F<k+1>; declared last-first so that each is declared before
    -- use (MT-POU-11). The call of F<k+1> inside F<k> is on line 3 of F<k>'s
    -- block of 5 lines; the chain F1..F<n> puts F<n> in the n-th frame.
    let chainSource n =
          src $
            concat
              [ [ "FUNCTION F" <> tshow k <> " : INT"
                , "VAR_INPUT A : INT; END_VAR"
                , if k == n then "F" <> tshow k <> " := A;" else "F" <> tshow k <> " := F" <> tshow (k + 1) <> "(A);"
                , "END_FUNCTION"
                , ""
                ]
              | k <- [n, n - 1 .. 1]
              ]
              ++ ["PROGRAM P", "VAR X : INT; END_VAR", "X := F1(3);", "END_PROGRAM"]
        -- F<k>'s block starts on line 5 * (n - k) + 1; its call on the 3rd line
        callLine n k = 5 * (n - k) + 3
    it "16 nested frames run" $
      fmap (\o -> (errorOf o, var "P.X" o)) (runP mastertoolXE 1 (chainSource 16)) `shouldBe` Right (Nothing, Just (VInt 3))
    it "the 17th is 2050 at the line where F16 calls F17" $
      fmap errorOf (runP mastertoolXE 1 (chainSource 17)) `shouldBe` Right (Just (runtimeError errCallDepth (callLine 17 16)))

  describe "runtime errors carry the source line (MT-DIAG-2, A24)" $ do
    let program =
          src
            [ "PROGRAM P" -- 1
            , "VAR" -- 2
            , "  V : ARRAY[1..5] OF INT;" -- 3
            , "  I, D : INT;" -- 4
            , "  M AT %M0020 : INT;" -- 5
            , "END_VAR" -- 6
            , "M := 1;" -- 7
            , "I := 6;" -- 8
            , "IF D = 0 THEN" -- 9
            , "  V[I] := 1;" -- 10
            , "END_IF;" -- 11
            , "M := 100 / D;" -- 12
            , "END_PROGRAM" -- 13
            ]
    it "2015 on line 10, OUTPUT1 FALSE, the earlier write persists" $
      fmap (\o -> (errorOf o, fmap crOutputs (lastResult o), operand "%M0020" o, band o)) (runP mastertoolXE 1 program)
        `shouldBe` Right (Just (runtimeError errIndex 10), Just (False, False, False), Just (VInt 1), map (Just . VInt) [10, 2015, 0, 0, 0])
    it "with the index clamped, 2020 on line 12" $
      fmap errorOf (runP mastertoolXE {pIndexOutOfRange = IndexClamp} 1 program) `shouldBe` Right (Just (runtimeError errDivisionByZero 12))

  describe "short-circuit from source (MT-OP-22, A17)" $ do
    let program = src ["PROGRAM P", "VAR A, B : INT; OK : BOOL; END_VAR", "A := 5;", "IF (B <> 0) AND (A / B > 1) THEN", "  OK := TRUE;", "END_IF;", "END_PROGRAM"]
    it "eager: 2020 on line 4" $ fmap errorOf (runP mastertoolXE 1 program) `shouldBe` Right (Just (runtimeError errDivisionByZero 4))
    it "short-circuit: no error" $ fmap errorOf (runP mastertoolXE {pShortCircuit = ShortCircuit} 1 program) `shouldBe` Right Nothing

  describe "FOR from source" $ do
    let program = src ["PROGRAM P", "VAR U : USINT; C : INT; END_VAR", "FOR U := 250 TO 255 DO", "  C := C + 1;", "END_FOR;", "END_PROGRAM"]
    it "FOR U := 250 TO 255 (USINT) runs 6 times under stop-at-end" $
      fmap (var "P.C") (runP mastertoolXE 1 program) `shouldBe` Right (Just (VInt 6))
    it "and meets the step budget under follow-overflow-policy" $
      fmap (fmap reCode . errorOf) (runP mastertoolXE {pForAtTypeMax = FollowOverflowPolicy, pStepBudget = 10000} 1 program) `shouldBe` Right (Just errExecutionTime)

  describe "mapping from source (MT-MAP)" $ do
    it "two REAL variables AT %F0000 alias one operand (MT-MAP-13)" $ do
      let program = src ["VAR", "  R1 AT %F0000 : REAL;", "  R2 AT %F0000 : REAL;", "END_VAR", "PROGRAM P", "R1 := 2.5;", "R2 := R2 * 2.0;", "END_PROGRAM"]
      fmap (operand "%F0000") (runP mastertoolXE 1 program) `shouldBe` Right (Just (VReal 5.0))
    it "an array AT %TM0010[5] addresses positions 5.. (MT-MAP-9)" $ do
      let program = src ["PROGRAM P", "VAR", "  T AT %TM0010[5] : ARRAY[1..3] OF INT;", "END_VAR", "T[3] := 42;", "END_PROGRAM"]
      fmap (operand "%TM0010[7]") (runP mastertoolXE 1 program) `shouldBe` Right (Just (VInt 42))
    it "an undeclared table position is 2002 before the first line" $ do
      let program = src ["PROGRAM P", "VAR", "  T AT %TM0030[98] : ARRAY[1..3] OF INT;", "END_VAR", "T[1] := 42;", "END_PROGRAM"]
      -- positions 98, 99, 100 of a 100-position table: 100 is missing
      fmap errorOf (runP mastertoolXE 1 program) `shouldBe` Right (Just (RuntimeError errTablePositionNotDeclared 0 (0, 30, 100)))

  describe "an F module (MT-PARAM-3, MT-PARAM-5)" $ do
    let program =
          src
            [ "PROGRAM F1"
            , "VAR_INPUT K : INT; END_VAR"
            , "VAR_IN_OUT ACC : INT; END_VAR"
            , "VAR_OUTPUT DOUBLE : INT; END_VAR"
            , "ACC := ACC + K;"
            , "DOUBLE := ACC * 2;"
            , "END_PROGRAM"
            ]
        call = defaultCallSpec {csChfIn = [ChfConstant KMConst 5, ChfOperand (OpSimple KM 10)], csChfOut = [ChfOperand (OpSimple KM 11)]}
    -- two calls: %M0010 goes 0 -> 5 -> 10; %M0011 = 2 * 10 after the second
    it "accumulates through the VAR_IN_OUT over two calls" $
      fmap (\o -> (operand "%M0010" o, operand "%M0011" o)) (runWith mastertoolXE FunctionModule [] [call, call] program)
        `shouldBe` Right (Just (VInt 10), Just (VInt 20))

  describe "manual examples" $ do
    it "EXPT(4, 2) = 16 (MT-OP-20)" $ do
      let program = src ["PROGRAM XXXXXX", "VAR", " base, resultado : INT;", " expoente  : USINT;", "END_VAR", "base  := 4;", "expoente := 2;", "resultado  :=  EXPT( base, expoente );", "END_PROGRAM"]
      fmap (var "XXXXXX.resultado") (runP mastertoolXE 1 program) `shouldBe` Right (Just (VInt 16))
    it "the FOR example adds Vetor[1..10] (all 0 by default, MT-VAR-3) and leaves I past the end" $ do
      let program = src ["PROGRAM X", "VAR i : INT; Vetor : ARRAY [1..10] OF INT := [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]; ACUMULADOR : INT; END_VAR", "FOR I := 1 TO 10 DO", "ACUMULADOR := ACUMULADOR + Vetor[ I ];", "END_FOR;", "END_PROGRAM"]
      fmap (\o -> (var "X.ACUMULADOR" o, var "X.i" o)) (runP mastertoolXE 1 program) `shouldBe` Right (Just (VInt 55), Just (VInt 11))
  where
    tshow :: Int -> Text
    tshow = T.pack . show
