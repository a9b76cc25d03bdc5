-- | The fast evaluator's standard FBs (Stref.IEC.Fast.StandardFB) against
-- their definitions (Stref.IEC.StandardFB): on random instances (any
-- values of the variables' types, hidden ones included), clocks and
-- policies, each twin leaves every variable as the definition does. The
-- expected values are the definitions', never the twin's.
module IEC.FastStandardFBSpec (spec) where

import Control.Monad.ST (runST)
import qualified Data.Map.Strict as M
import Data.Maybe (isNothing)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Vector as V
import Stref.IEC.Checked
import Stref.IEC.Fast.StandardFB (Twin (..), twin, twinNames)
import Stref.IEC.StandardFB (standardFBs)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Test.Hspec
import Test.QuickCheck

-- | The policies the standard FBs depend on, each alternative.
policies :: Gen Policies
policies = do
  base <- elements [tecomat, nexto]
  q <- elements [SameCycle, NextCycle]
  d <- elements [EqualZero, AtMostZero]
  f <- elements [FTrigTrue, FTrigFalse]
  pure base {pTimerQ = q, pDownCounterQ = d, pFTrigInitial = f}

-- | A value of a variable's type, often at the edges that matter (0, the
-- counters' limits, times around the clock).
valueOf :: Type -> Gen Value
valueOf = \case
  TElem BOOL -> VBool <$> arbitrary
  TElem TIME -> VTime TIME <$> frequency [(3, choose (0, 200)), (1, choose (-5, 5)), (1, elements [2147483647, -2147483648])]
  TElem e | isInt e -> let (lo, hi) = intRange e in VInt e <$> frequency [(3, choose (max lo (-3), min hi 60)), (1, elements [lo, lo + 1, hi - 1, hi])]
  t -> pure (defaultValue t)

-- | The definition and the twin of one FB, on one instance: the variables
-- each leaves.
compareOn :: Policies -> Text -> Integer -> M.Map Text Value -> Maybe (M.Map Text Value, M.Map Text Value)
compareOn pol name clock vars = do
  d <- lookup name (standardFBs pol)
  meaning <- case pdBody d of
    Native f -> Just f
    Statements _ -> Nothing
  let keys = M.keys vars
      slots = M.fromList (zip keys [0 ..])
  Twin run <- twin pol name (`M.lookup` slots)
  let after = runST $ do
        v <- V.thaw (V.fromList (M.elems vars))
        run clock v 0
        V.toList <$> V.freeze v
  pure (meaning pol clock vars, M.fromList (zip keys after))

spec :: Spec
spec = describe "IEC.Fast.StandardFB: the standard FBs on the fast evaluator's slots" $ do
  it "every FB with a twin is a standard FB of both libraries" $
    [n | n <- twinNames, pol <- [tecomat, nexto], isNothing (lookup n (standardFBs pol))] `shouldBe` []
  mapM_ agreeing twinNames
  where
    agreeing name = it ("leave " <> T.unpack name <> "'s variables as its definition does") $
      withMaxSuccess 400 . forAll policies $ \pol ->
        case lookup name (standardFBs pol) of
          Nothing -> counterexample "no such FB" False
          Just d -> forAll (M.fromList <$> mapM (\v -> (viKey v,) <$> valueOf (viType v)) (pdVars d)) $ \vars ->
            forAll (frequency [(3, choose (0, 300)), (1, elements [0, 2147483647])]) $ \clock ->
              case compareOn pol name clock vars of
                Nothing -> counterexample "no twin" False
                Just (reference, fast) -> counterexample (show vars <> " at " <> show clock) (fast === reference)
