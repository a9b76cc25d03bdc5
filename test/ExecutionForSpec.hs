-- | FOR (MT-STMT-15..21, decisions A13, A14) under every alternative of
-- @for-bounds@ and @for-at-type-max@.
module ExecutionForSpec (spec) where

import Execution.Build
import Stref.Checked
import Stref.Diagnostics
import Stref.Execution
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec

i, c, n, s, u :: Var
i = dataVar "I" (Basic INT) 0
c = dataVar "C" (Basic INT) 1 -- iteration counter
n = dataVar "N" (Basic INT) 2
s = dataVar "S" (Basic INT) 3
u = dataVar "U" (Basic USINT) 4

ov :: Var
ov = dataVar "OV" (Basic BOOL) 5

count :: CStmt
count = assign 3 c (add 3 (rd c) (int 1))

runBody :: Policies -> [CStmt] -> CallResult
runBody p body = snd (runOnce p {pStepBudget = 100000} (build spec0 {msVars = [i, c, n, s, u, ov], msBody = body}))

counted :: Policies -> [CStmt] -> Maybe Value
counted p = varValue "P.C" . runBody p

stopAtEnd, followSat, followWrap, followTrap :: Policies
stopAtEnd = mastertoolXE
followSat = mastertoolXE {pForAtTypeMax = FollowOverflowPolicy}
followWrap = followSat {pOverflow = Wrap}
followTrap = followSat {pOverflow = Trap}

everyIteration :: Policies -> Policies
everyIteration p = p {pForBounds = ForEveryIteration}

spec :: Spec
spec = describe "Execution: FOR" $ do
  let allPolicies =
        [ (name ++ ", " ++ bounds, f p)
        | (name, p) <- [("stop-at-end", stopAtEnd), ("follow/saturate", followSat), ("follow/wrap", followWrap), ("follow/trap", followTrap)]
        , (bounds, f) <- [("once", id), ("every-iteration", everyIteration)]
        ]
  describe "ordinary loops behave alike under every alternative" $
    mapM_
      ( \(name, p) -> describe name $ do
          it "FOR I := 1 TO 10 runs 10 times (MT-STMT-18)" $
            counted p [SFor 2 i (int 1) (int 10) (int 1) [count]] `shouldBe` Just (VInt 10)
          it "FOR I := 10 TO 1 never runs" $
            counted p [SFor 2 i (int 10) (int 1) (int 1) [count]] `shouldBe` Just (VInt 0)
          it "FOR I := 10 TO 1 BY -3 counts down while I >= 1: 10, 7, 4, 1 (A13)" $
            counted p [SFor 2 i (int 10) (int 1) (int (-3)) [count]] `shouldBe` Just (VInt 4)
          it "FOR I := 1 TO 10 BY 4: 1, 5, 9" $
            counted p [SFor 2 i (int 1) (int 10) (int 4) [count]] `shouldBe` Just (VInt 3)
          it "EXIT leaves the FOR (MT-STMT-12)" $ do
            let r = runBody p [SFor 2 i (int 1) (int 10) (int 1) [count, SIf [(4, cmp OpEq (rd i) (int 3), [SExit 4])] []]]
            (varValue "P.C" r, varValue "P.I" r) `shouldBe` (Just (VInt 3), Just (VInt 3))
          -- (empty bodies below: the budget then always runs out on a FOR test)
          it "a step of 0 with start <= end loops until the budget (2030 on the FOR line)" $
            crError (runBody p [SFor 2 i (int 1) (int 5) (int 0) []]) `shouldBe` Just (runtimeError errExecutionTime 2)
          it "a step of 0 with start > end never runs" $
            counted p [SFor 2 i (int 5) (int 1) (int 0) [count]] `shouldBe` Just (VInt 0)
      )
      allPolicies

  describe "for-at-type-max = stop-at-end (A13)" $ do
    it "FOR U := 250 TO 255 on USINT runs 6 times and ends without error" $ do
      let r = runBody stopAtEnd [SFor 2 u (usint 250) (usint 255) (usint 1) [count]]
      (varValue "P.C" r, crError r) `shouldBe` (Just (VInt 6), Nothing)
    it "FOR I := 32760 TO 32767 BY 5 on INT runs for 32760 and 32765" $
      counted stopAtEnd [SFor 2 i (int 32760) (int 32767) (int 5) [count]] `shouldBe` Just (VInt 2)
    it "FOR I := -32766 TO -32768 BY -1 runs 3 times" $
      counted stopAtEnd [SFor 2 i (int (-32766)) (int (-32768)) (int (-1)) [count]] `shouldBe` Just (VInt 3)
    it "leaves the control variable one step past the end when that is representable" $
      varValue "P.I" (runBody stopAtEnd [SFor 2 i (int 1) (int 10) (int 1) []]) `shouldBe` Just (VInt 11)
    it "leaves the control variable at the end when the next step would overflow" $
      varValue "P.U" (runBody stopAtEnd [SFor 2 u (usint 250) (usint 255) (usint 1) []]) `shouldBe` Just (VUSInt 255)
    -- 32767 + 1 sets INTERNAL_OVERFLOW; the FOR increments (no overflow) do
    -- not touch it under stop-at-end, but clear it as ordinary additions
    -- under follow-overflow-policy
    let flagAfterLoop p =
          varValue "P.OV" (runBody p [assign 1 n (add 1 (int 32767) (int 1)), SFor 2 i (int 1) (int 2) (int 1) [], assign 4 ov (rd overflowFlag)])
    it "does not touch INTERNAL_OVERFLOW" $ flagAfterLoop stopAtEnd `shouldBe` Just (VBool True)
    it "(follow-overflow-policy: the increment is an addition and clears the flag)" $ flagAfterLoop followSat `shouldBe` Just (VBool False)

  describe "for-at-type-max = follow-overflow-policy" $ do
    it "saturate: U stays at 255 and never passes the end: 2030" $
      crError (runBody followSat [SFor 2 u (usint 250) (usint 255) (usint 1) []]) `shouldBe` Just (runtimeError errExecutionTime 2)
    it "wrap: U wraps to 0 and loops forever: 2030" $
      crError (runBody followWrap [SFor 2 u (usint 250) (usint 255) (usint 1) []]) `shouldBe` Just (runtimeError errExecutionTime 2)
    it "trap: the overflowing increment after the 6th body is a trap on the FOR line" $ do
      let r = runBody followTrap [SFor 2 u (usint 250) (usint 255) (usint 1) [count]]
      (crError r, varValue "P.C" r) `shouldBe` (Just (runtimeError trapOverflow 2), Just (VInt 6))

  describe "for-bounds (MT-STMT-19, A14)" $ do
    -- the body raises N from 3 to 5: once, the end stays 3; every
    -- iteration, the test sees 5
    let endChanges = [assign 1 n (int 3), SFor 2 i (int 1) (rd n) (int 1) [count, assign 3 n (int 5)]]
    it "once: TO is evaluated once" $ counted mastertoolXE endChanges `shouldBe` Just (VInt 3)
    it "every-iteration: TO is evaluated at every test" $ counted (everyIteration mastertoolXE) endChanges `shouldBe` Just (VInt 5)
    -- the body sets S from 1 to 3. once: 10 iterations. every-iteration: the
    -- increment uses the step of the preceding test: I = 1 (step 1), 2
    -- (step 3), 5, 8, then 11 ends it: 4 iterations
    let stepChanges = [assign 1 s (int 1), SFor 2 i (int 1) (int 10) (rd s) [count, assign 3 s (int 3)]]
    it "once: BY is evaluated once" $ counted mastertoolXE stepChanges `shouldBe` Just (VInt 10)
    it "every-iteration: BY is evaluated at every test" $ counted (everyIteration mastertoolXE) stepChanges `shouldBe` Just (VInt 4)
    it "the start is assigned before the end is evaluated (TO I + 2 with I := 5 runs 5, 6, 7)" $
      counted mastertoolXE [SFor 2 i (int 5) (add 2 (rd i) (int 2)) (int 1) [count]] `shouldBe` Just (VInt 3)
