-- | Statements (catalogue §6) on hand-built checked programs.
module ExecutionStatementSpec (spec) where

import Execution.Build
import Stref.Checked
import Stref.Diagnostics
import Stref.Execution
import Stref.Operands (defaultPlcConfig)
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec

x, y, b :: Var
x = dataVar "X" (Basic INT) 0
y = dataVar "Y" (Basic INT) 1
b = dataVar "B" (Basic BOOL) 2

-- | Run a body over X, Y, B (all starting at their defaults) under a policy.
runBody :: Policies -> [CStmt] -> CallResult
runBody p body = snd (runOnce p (build spec0 {msVars = [x, y, b], msBody = body}))

xy :: CallResult -> (Maybe Value, Maybe Value)
xy r = (varValue "P.X" r, varValue "P.Y" r)

inc :: Line -> Var -> CStmt
inc l v = assign l v (add l (rd v) (int 1))

spec :: Spec
spec = describe "Execution: statements" $ do
  describe "assignment (MT-STMT-2) and a successful call (MT-DIAG-4)" $ do
    let (st, r) = runOnce mastertoolXE (build spec0 {msVars = [x], msBody = [assign 3 x (int 5)]})
    it "stores the value" $ varValue "P.X" r `shouldBe` Just (VInt 5)
    it "writes [-32768,0,0,0,0] into the diagnostic band" $ bandOf st `shouldBe` [-32768, 0, 0, 0, 0]
    it "leaves OUTPUT1 TRUE, OUTPUT2/3 FALSE (MT-SIG-4)" $ crOutputs r `shouldBe` (True, False, False)
    it "reports no error" $ crError r `shouldBe` Nothing

  describe "IF (MT-STMT-6)" $ do
    let ifStmt c1 c2 = SIf [(2, bool c1, [assign 2 x (int 1)]), (3, bool c2, [assign 3 x (int 2)]), (4, bool True, [assign 4 x (int 3)])]
    it "runs only the first true branch" $
      varValue "P.X" (runBody mastertoolXE [ifStmt False True [assign 5 x (int 4)]]) `shouldBe` Just (VInt 2)
    it "runs the THEN branch when the first test holds" $
      varValue "P.X" (runBody mastertoolXE [ifStmt True True []]) `shouldBe` Just (VInt 1)
    it "runs ELSE when every test fails" $
      varValue "P.X" (runBody mastertoolXE [SIf [(2, bool False, [assign 2 x (int 1)])] [assign 3 x (int 9)]]) `shouldBe` Just (VInt 9)
    it "does nothing without ELSE when every test fails" $
      varValue "P.X" (runBody mastertoolXE [assign 1 x (int 7), SIf [(2, bool False, [assign 2 x (int 1)])] []]) `shouldBe` Just (VInt 7)

  describe "CASE (MT-STMT-8)" $ do
    let caseOn v =
          [ assign 1 x (int v)
          , SCase 2 (rd x) [([(1, 1)], [assign 3 y (int 1)]), ([(2, 2), (5, 10)], [assign 4 y (int 2)]), ([(7, 7)], [assign 5 y (int 3)])] [assign 6 y (int 9)]
          ]
    it "runs the first arm whose label matches (7 is in 5..10 before the arm 7)" $
      varValue "P.Y" (runBody mastertoolXE (caseOn 7)) `shouldBe` Just (VInt 2)
    it "includes both ends of a range" $ do
      varValue "P.Y" (runBody mastertoolXE (caseOn 5)) `shouldBe` Just (VInt 2)
      varValue "P.Y" (runBody mastertoolXE (caseOn 10)) `shouldBe` Just (VInt 2)
    it "matches a single value" $ varValue "P.Y" (runBody mastertoolXE (caseOn 1)) `shouldBe` Just (VInt 1)
    it "runs ELSE when nothing matches" $ varValue "P.Y" (runBody mastertoolXE (caseOn 11)) `shouldBe` Just (VInt 9)
    it "runs nothing without ELSE when nothing matches" $
      varValue "P.Y" (runBody mastertoolXE [assign 1 x (int 4), SCase 2 (rd x) [([(1, 3)], [assign 3 y (int 1)])] []]) `shouldBe` Just (VInt 0)

  describe "WHILE (MT-STMT-13)" $ do
    it "tests before each iteration: counts X up to 5" $
      varValue "P.X" (runBody mastertoolXE [SWhile 2 (cmp OpLt (rd x) (int 5)) [inc 3 x]]) `shouldBe` Just (VInt 5)
    it "never runs the body when the test is FALSE at first" $
      varValue "P.Y" (runBody mastertoolXE [SWhile 2 (bool False) [assign 3 y (int 1)]]) `shouldBe` Just (VInt 0)

  describe "REPEAT (MT-STMT-14)" $ do
    it "runs the body at least once" $
      varValue "P.Y" (runBody mastertoolXE [SRepeat [inc 2 y] 3 (bool True)]) `shouldBe` Just (VInt 1)
    it "ends when the test is TRUE" $
      varValue "P.X" (runBody mastertoolXE [SRepeat [inc 2 x] 3 (cmp OpGe (rd x) (int 3))]) `shouldBe` Just (VInt 3)

  describe "EXIT (MT-STMT-12)" $ do
    -- the inner loop runs its body once per outer iteration, then leaves;
    -- the outer loop goes on: X = 3, Y = 3
    it "leaves only the innermost loop" $
      xy (runBody mastertoolXE [SWhile 1 (cmp OpLt (rd x) (int 3)) [inc 2 x, SWhile 3 (bool True) [inc 4 y, SExit 5]]])
        `shouldBe` (Just (VInt 3), Just (VInt 3))
    it "leaves a REPEAT" $
      varValue "P.Y" (runBody mastertoolXE [SRepeat [inc 2 y, SExit 3] 4 (bool False)]) `shouldBe` Just (VInt 1)

  describe "RETURN in the program (MT-STMT-5)" $ do
    let r = runBody mastertoolXE [assign 1 x (int 1), SIf [(2, bool True, [SReturn 3])] [], assign 4 x (int 2)]
    it "stops the program" $ varValue "P.X" r `shouldBe` Just (VInt 1)
    it "is a normal end" $ crError r `shouldBe` Nothing
    it "keeps what the program wrote to OUTPUT1" $
      crOutputs (runBody mastertoolXE [assign 1 out1 (bool False), assign 2 out2 (bool True), SReturn 3])
        `shouldBe` (False, True, False)

  describe "INPUT2 and INTERNAL_OVERFLOW (MT-SIG-2, MT-OP-7, A5)" $ do
    it "reads INPUT2 from the call" $ do
      let cm = build spec0 {msVars = [b], msBody = [assign 1 b (rd in2)]}
          (_, r) = runWith mastertoolXE defaultPlcConfig defaultCallInput {ciInputs = (True, False, True)} initialPlcState cm
      varValue "P.B" r `shouldBe` Just (VBool False)
    -- 32767 + 1 saturates (MT-OP-6) and sets the flag; 1 + 1 clears it again
    it "is set by an overflowing addition and cleared by the next one" $ do
      let r = runBody mastertoolXE [assign 1 x (add 1 (int 32767) (int 1)), assign 2 b (rd overflowFlag), assign 3 y (add 3 (int 1) (int 1))]
      (varValue "P.X" r, varValue "P.B" r) `shouldBe` (Just (VInt 32767), Just (VBool True))
    it "starts FALSE" $
      varValue "P.B" (runBody mastertoolXE [assign 1 b (rd overflowFlag)]) `shouldBe` Just (VBool False)

  describe "short-circuit policy (decision A17)" $ do
    -- FALSE AND (1 / 0 = 0): the right operand divides by zero on line 4
    let guarded = [assign 4 b (andE (bool False) (cmp OpEq (divide 4 (int 1) (int 0)) (int 0)))]
        orGuarded = [assign 5 b (orE (bool True) (cmp OpEq (divide 5 (int 1) (int 0)) (int 0)))]
    it "eager: evaluates the right operand of AND (2020 on line 4)" $
      crError (runBody mastertoolXE guarded) `shouldBe` Just (runtimeError errDivisionByZero 4)
    it "eager: evaluates the right operand of OR (2020 on line 5)" $
      crError (runBody mastertoolXE orGuarded) `shouldBe` Just (runtimeError errDivisionByZero 5)
    it "short-circuit: skips the right operand of AND when the left is FALSE" $ do
      let r = runBody mastertoolXE {pShortCircuit = ShortCircuit} guarded
      (crError r, varValue "P.B" r) `shouldBe` (Nothing, Just (VBool False))
    it "short-circuit: skips the right operand of OR when the left is TRUE" $ do
      let r = runBody mastertoolXE {pShortCircuit = ShortCircuit} orGuarded
      (crError r, varValue "P.B" r) `shouldBe` (Nothing, Just (VBool True))
    it "short-circuit: still evaluates the right operand when the left does not decide" $
      crError (runBody mastertoolXE {pShortCircuit = ShortCircuit} [assign 6 b (andE (bool True) (cmp OpEq (divide 6 (int 1) (int 0)) (int 0)))])
        `shouldBe` Just (runtimeError errDivisionByZero 6)

  describe "step budget (MT-EXEC-7)" $ do
    it "stops an endless WHILE with 2030 on the loop's line" $
      crError (runBody mastertoolXE {pStepBudget = 1000} [SWhile 4 (bool True) []]) `shouldBe` Just (runtimeError errExecutionTime 4)
    it "stops an endless REPEAT with 2030 on the UNTIL line" $
      crError (runBody mastertoolXE {pStepBudget = 1000} [SRepeat [] 7 (bool False)]) `shouldBe` Just (runtimeError errExecutionTime 7)
    it "counts executed statements and loop tests exactly" $
      -- 1 (WHILE) + 4 tests + 3 bodies: X goes 0 -> 3
      crSteps (runBody mastertoolXE [SWhile 1 (cmp OpLt (rd x) (int 3)) [inc 2 x]]) `shouldBe` 8
