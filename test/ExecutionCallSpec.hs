-- | Function calls (MT-POU, MT-SCOPE-7), the module life cycle (MT-EXEC-9),
-- lifetime and mapping (MT-MAP).
module ExecutionCallSpec (spec) where

import qualified Data.Text as T
import Execution.Build
import Stref.Checked
import Stref.Diagnostics
import Stref.Execution
import Stref.Operands
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec

x, y, g :: Var
x = dataVar "X" (Basic INT) 0
y = dataVar "Y" (Basic INT) 1
g = dataVar "G" (Basic INT) 2

result :: Var
result = frameVar "F" (Basic INT) 0

paramA :: Var
paramA = frameVar "A" (Basic INT) 1

-- | F(A) := A + 1
plusOne :: CFunction
plusOne = function "PLUS1" INT [paramA] [] [assign 10 result (add 10 (rd paramA) (int 1))]

-- | ACC(A): local L starts at 0 on every call; L := L + A; ACC := L
accumulate :: CFunction
accumulate =
  let l = frameVar "L" (Basic INT) 2
   in function "ACC" INT [paramA] [VarInit l Nothing] [assign 20 l (add 20 (rd l) (rd paramA)), assign 21 result (rd l)]

-- | ONLYPOS(A): IF A > 0 THEN ONLYPOS := 7 END_IF
onlyPositive :: CFunction
onlyPositive = function "ONLYPOS" INT [paramA] [] [SIf [(30, cmp OpGt (rd paramA) (int 0), [assign 30 result (int 7)])] []]

-- | SETG(A): G := A; SETG := A (a side effect on a global)
setGlobal :: CFunction
setGlobal = function "SETG" INT [paramA] [] [assign 40 g (rd paramA), assign 41 result (rd paramA)]

-- | A chain of n functions: F_k(A) := F_(k+1)(A) on line 100 + k, the last
-- one returns A. The program calls F_0, so F_(n-1) is the n-th nested frame.
chain :: Int -> [CFunction]
chain count =
  [ function ("F" <> T.pack (show k)) INT [paramA] [] [assign (100 + k) result (if k == count - 1 then rd paramA else CCall (100 + k) (k + 1) INT [rd paramA])]
  | k <- [0 .. count - 1]
  ]

callModule :: [CFunction] -> [CStmt] -> CModule
callModule fs body = build spec0 {msVars = [x, y, g], msFunctions = fs, msBody = body}

run :: [CFunction] -> [CStmt] -> CallResult
run fs body = snd (runOnce mastertoolXE (callModule fs body))

spec :: Spec
spec = describe "Execution: calls and the module life cycle" $ do
  describe "function calls (MT-POU-3, MT-POU-4)" $ do
    it "returns the value of the result slot" $
      varValue "P.X" (run [plusOne] [assign 1 x (CCall 1 0 INT [int 4])]) `shouldBe` Just (VInt 5)
    it "initialises locals on every call (MT-SCOPE-7): ACC(1) twice gives 1 twice" $ do
      let r = run [accumulate] [assign 1 x (CCall 1 0 INT [int 1]), assign 2 y (CCall 2 0 INT [int 1])]
      (varValue "P.X" r, varValue "P.Y" r) `shouldBe` (Just (VInt 1), Just (VInt 1))
    it "starts the result slot at the type default on every call" $ do
      let r = run [onlyPositive] [assign 1 x (CCall 1 0 INT [int 1]), assign 2 y (CCall 2 0 INT [int 0])]
      (varValue "P.X" r, varValue "P.Y" r) `shouldBe` (Just (VInt 7), Just (VInt 0))
    it "a call statement discards the result but keeps the side effects (MT-STMT-3)" $
      varValue "P.G" (run [setGlobal] [SCall 1 0 [int 9]]) `shouldBe` Just (VInt 9)
    it "evaluates arguments and calls left to right (A18): SETG(1) + SETG(2) leaves G = 2" $ do
      let r = run [setGlobal] [assign 1 x (add 1 (CCall 1 0 INT [int 1]) (CCall 1 0 INT [int 2]))]
      (varValue "P.X" r, varValue "P.G" r) `shouldBe` (Just (VInt 3), Just (VInt 2))
    it "RETURN leaves the function with the result assigned so far (MT-STMT-4)" $ do
      let early = function "EARLY" INT [paramA] [] [assign 50 result (int 1), SReturn 51, assign 52 result (int 2)]
      varValue "P.X" (run [early] [assign 1 x (CCall 1 0 INT [int 0])]) `shouldBe` Just (VInt 1)
    it "restores the caller's frame after a nested call" $ do
      -- OUTER(A): L := A; OUTER := PLUS1(A + 10) + L, so OUTER(1) = 12 + 1 = 13
      let l = frameVar "L" (Basic INT) 2
          outer = function "OUTER" INT [paramA] [VarInit l Nothing] [assign 60 l (rd paramA), assign 61 result (add 61 (CCall 61 0 INT [add 61 (rd paramA) (int 10)]) (rd l))]
      varValue "P.X" (run [plusOne, outer] [assign 1 x (CCall 1 1 INT [int 1])]) `shouldBe` Just (VInt 13)

  describe "nesting depth (MT-POU-9, A27)" $ do
    it "allows 16 nested function frames" $ do
      let r = run (chain 16) [assign 3 x (CCall 3 0 INT [int 5])]
      (crError r, varValue "P.X" r) `shouldBe` (Nothing, Just (VInt 5))
    it "raises 2050 at the line of the call that would open the 17th" $ do
      -- F15 (the 16th frame) calls F16 on line 100 + 15
      let (st, r) = runOnce mastertoolXE (callModule (chain 17) [assign 3 x (CCall 3 0 INT [int 5])])
      crError r `shouldBe` Just (runtimeError errCallDepth 115)
      bandOf st `shouldBe` [115, 2050, 0, 0, 0]
      crOutputs r `shouldBe` (False, False, False)

  describe "lifetime (MT-SCOPE-7, MT-MAP-1)" $ do
    let counter = build spec0 {msVars = [x, m10], msBody = [assign 1 x (add 1 (rd x) (int 1)), assign 2 m10 (add 2 (rd m10) (int 1))]}
        m10 = mappedVar "M" (Basic INT) "%M0010"
    it "per-call: an unmapped variable starts again on every call" $ do
      let (_, rs) = runN mastertoolXE 2 initialPlcState counter
      map (varValue "P.X") rs `shouldBe` [Just (VInt 1), Just (VInt 1)]
    it "per-call: a mapped variable keeps its value (it is the operand)" $ do
      let (st, _) = runN mastertoolXE 2 initialPlcState counter
      operandValue st "%M0010" INT `shouldBe` VInt 2
    it "retained: the data area survives between calls" $ do
      let (_, rs) = runN mastertoolXE {pLifetime = Retained} 3 initialPlcState counter
      map (varValue "P.X") rs `shouldBe` [Just (VInt 1), Just (VInt 2), Just (VInt 3)]
    let withInit = build spec0 {msVars = [m10], msInits = [("M", InitScalar (VInt 5))], msBody = [assign 2 m10 (add 2 (rd m10) (int 1))]}
    it "per-call: a mapped initialiser is written on every call (A3, MT-MAP-15)" $ do
      let (st, _) = runN mastertoolXE 2 initialPlcState withInit
      operandValue st "%M0010" INT `shouldBe` VInt 6
    it "retained: a mapped initialiser is written on the first call only" $ do
      let (st, _) = runN mastertoolXE {pLifetime = Retained} 2 initialPlcState withInit
      operandValue st "%M0010" INT `shouldBe` VInt 7
    it "an unmapped initialiser gives the start value (MT-VAR-4)" $ do
      let r = snd (runOnce mastertoolXE (build spec0 {msVars = [x], msInits = [("X", InitScalar (VInt 40))], msBody = [assign 1 y (rd x)]}))
      varValue "P.X" r `shouldBe` Just (VInt 40)
    it "a mapped variable without initialiser is not written (MT-VAR-3)" $ do
      let st0 = initialPlcState {psMemory = writeOperand (op "%M0010") (VInt 33) emptyMemory}
          cm = build spec0 {msVars = [m10, x], msBody = [assign 1 x (rd m10)]}
          (_, r) = runWith mastertoolXE defaultPlcConfig defaultCallInput st0 cm
      varValue "P.X" r `shouldBe` Just (VInt 33)

  describe "mapping (MT-MAP)" $ do
    it "aliases: two variables AT one operand see each other's writes (MT-MAP-13)" $ do
      let a = mappedVar "A" (Basic INT) "%M0010"
          w = mappedVar "W" (Basic WORD) "%M0010"
          cw = dataVar "CW" (Basic WORD) 3
          r = snd (runOnce mastertoolXE (build spec0 {msVars = [a, w, cw], msBody = [assign 1 a (int (-1)), assign 2 cw (rd w)]}))
      varValue "P.CW" r `shouldBe` Just (VWord 0xFFFF)
    it "a BOOL AT %M0006.6 changes only bit 6 (MT-MAP-6)" $ do
      let bt = mappedVar "BT" (Basic BOOL) "%M0006.6"
          st0 = initialPlcState {psMemory = writeOperand (op "%M0006") (VWord 0x0F0F) emptyMemory}
          set v = build spec0 {msVars = [bt], msBody = [assign 1 bt (bool v)]}
          (st1, _) = runWith mastertoolXE defaultPlcConfig defaultCallInput st0 (set True)
          (st2, _) = runWith mastertoolXE defaultPlcConfig defaultCallInput st1 (set False)
      -- 16#0F0F with bit 6 (16#0040) set is 16#0F4F; cleared again 16#0F0F
      (operandValue st1 "%M0006" WORD, operandValue st2 "%M0006" WORD) `shouldBe` (VWord 0x0F4F, VWord 0x0F0F)
    it "array element k of AT %M0100 : ARRAY[5..7] is %M(100 + k - 5) (MT-MAP-9)" $ do
      let v = mappedVar "V" (Array 5 7 INT) "%M0100"
          (st, _) = runOnce mastertoolXE (build spec0 {msVars = [v], msBody = [assignAt 1 v (dint 6) (int 9), assignAt 2 v (dint 7) (int 8)]})
      map (\o -> operandValue st o INT) ["%M0100", "%M0101", "%M0102"] `shouldBe` [VInt 0, VInt 9, VInt 8]
    it "array element k of AT %TM0010[3] : ARRAY[1..4] is position 3 + k - 1" $ do
      let v = mappedVar "T" (Array 1 4 INT) "%TM0010[3]"
          (st, _) = runOnce mastertoolXE (build spec0 {msVars = [v], msBody = [assignAt 1 v (dint 4) (int 8)]})
      operandValue st "%TM0010[6]" INT `shouldBe` VInt 8
    it "observes arrays element-wise as P.V[k]" $ do
      let v = dataVar "V" (Array 1 2 INT) 10
          r = snd (runOnce mastertoolXE (build spec0 {msVars = [v], msInits = [("V", InitArray [VInt 3, VInt 4])], msBody = [assignAt 1 v (dint 2) (int 7)]}))
      (varValue "P.V[1]" r, varValue "P.V[2]" r) `shouldBe` (Just (VInt 3), Just (VInt 7))

  describe "INPUT1 FALSE (MT-SIG-3)" $ do
    let m10 = mappedVar "M" (Basic INT) "%M0010"
        cm = build spec0 {msVars = [m10], msBody = [assign 1 m10 (int 5)]}
        (st, r) = runWith mastertoolXE defaultPlcConfig defaultCallInput {ciInputs = (False, True, True)} initialPlcState cm
    it "does not run the module" $ operandValue st "%M0010" INT `shouldBe` VInt 0
    it "leaves the diagnostics untouched" $ bandOf st `shouldBe` [0, 0, 0, 0, 0]
    it "reports OUTPUT1..3 FALSE" $ (crOutputs r, crExecuted r) `shouldBe` ((False, False, False), False)
