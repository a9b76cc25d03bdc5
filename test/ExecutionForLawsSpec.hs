-- | Properties of FOR under stop-at-end (A13): the number of iterations is
-- the number of values start, start + step, ... that do not pass the end,
-- with no overflow, even next to the type's limits.
module ExecutionForLawsSpec (spec) where

import Execution.Build
import Stref.Checked
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec
import Test.QuickCheck

i, c :: Var
i = dataVar "I" (Basic INT) 0
c = dataVar "C" (Basic DINT) 1

-- | Values near the limits of INT and near zero.
intNear :: Gen Integer
intNear = do
  base <- elements [-32768, -40, 0, 32700]
  off <- choose (0, 67)
  pure (base + off)

-- | The iteration count computed by hand: the values start + k * step
-- (k = 0, 1, ...) that stay on the start side of the end.
expectedCount :: Integer -> Integer -> Integer -> Integer
expectedCount start end step
  | step > 0 = if start > end then 0 else (end - start) `div` step + 1
  | otherwise = if start < end then 0 else (start - end) `div` negate step + 1

loopCount :: Policies -> Integer -> Integer -> Integer -> Maybe Value
loopCount p start end step =
  varValue "P.C" $
    snd $
      runOnce p {pStepBudget = 10000000} $
        build spec0 {msVars = [i, c], msBody = [SFor 2 i (int start) (int end) (int step) [assign 3 c (add 3 (rd c) (dint 1))]]}

spec :: Spec
spec = describe "Execution: FOR laws (stop-at-end)" $ do
  it "runs as many times as there are values from start towards end, also at the INT limits" $
    property $
      forAll intNear $ \start -> forAll intNear $ \end ->
        forAll (elements [1, 2, 3, 7, 100, -1, -2, -5]) $ \step ->
          forAll (elements [ForOnce, ForEveryIteration]) $ \bounds ->
            loopCount mastertoolXE {pForBounds = bounds} start end step === Just (VDInt (fromInteger (expectedCount start end step)))
