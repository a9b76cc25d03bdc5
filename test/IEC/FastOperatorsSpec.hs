-- | The fast evaluator's operators, stores and conversions
-- (Stref.IEC.Fast.Operators) against the readable ones ('binary', 'fitWhy',
-- 'convert'): on random operators,
-- types, values (in and out of their type's range, of the type or of
-- another) and policies, each gives the readable one's outcome (compared
-- as shown, so that a NaN equals itself). The
-- expected outcome is always the readable function's.
module IEC.FastOperatorsSpec (spec) where

import Stref.IEC.Conversions (convert)
import Stref.IEC.Eval (fitWhy)
import Stref.IEC.Fast.Operators
import Stref.IEC.Operators (binary)
import Stref.IEC.Syntax (BinOp (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Test.Hspec
import Test.QuickCheck

-- | The policies the operators and stores depend on, each alternative.
policies :: Gen Policies
policies = do
  base <- elements [tecomat, nexto, mastertoolXE]
  o <- chooseEnum (minBound, maxBound)
  w <- chooseEnum (minBound, maxBound)
  d <- chooseEnum (minBound, maxBound)
  mz <- chooseEnum (minBound, maxBound)
  ms <- chooseEnum (minBound, maxBound)
  ni <- chooseEnum (minBound, maxBound)
  sr <- chooseEnum (minBound, maxBound)
  tr <- chooseEnum (minBound, maxBound)
  bs <- chooseEnum (minBound, maxBound)
  pure base {pOverflow = o, pArithWidth = w, pDivZero = d, pModZero = mz, pModSign = ms, pNarrowInt = ni, pSubrange = sr, pTimeRange = tr, pBitStringArithmetic = bs}

-- | The integer types, BOOL and the others the fast operators leave alone.
types :: Gen Type
types =
  frequency
    [ (8, TElem <$> elements [SINT, USINT, BYTE, INT, UINT, WORD, DINT, UDINT, DWORD])
    , (1, TElem <$> elements [LINT, ULINT, LWORD, BOOL, REAL, TIME])
    , (1, (\(lo, hi) -> TSubrange INT (min lo hi) (max lo hi)) <$> ((,) <$> choose (-20, 20) <*> choose (-20, 20)))
    ]

-- | A value for an operand or a store of this type: mostly of the type and
-- in its range, at its edges, sometimes beyond them (a value computed in
-- DINT under promote-32) or of another type.
valueFor :: Type -> Gen Value
valueFor t = case t of
  TElem e | isInt e -> ints e (intRange e)
  TSubrange e lo hi -> ints e (lo, hi)
  TElem BOOL -> VBool <$> arbitrary
  TElem REAL -> VReal <$> arbitrary
  TElem TIME -> VTime TIME <$> choose (-100, 100)
  _ -> pure (VBool False)
  where
    ints e (lo, hi) =
      frequency
        [ (6, VInt e <$> choose (max lo (-40), min hi 40))
        , (3, VInt e <$> elements [lo, lo + 1, hi - 1, hi, 0, -1])
        , (2, VInt e <$> choose (lo, hi))
        , (1, VInt e <$> choose (-2 ^ (40 :: Int), 2 ^ (40 :: Int)))
        , (1, VInt DINT <$> choose (-5, 5))
        , (1, VInt e <$> elements [2 ^ (70 :: Int), -(2 ^ (70 :: Int))])
        ]

spec :: Spec
spec = describe "IEC.Fast.Operators: the fast evaluator's operators against the readable ones" $ do
  it "binaryOn gives binary's outcome" $
    withMaxSuccess 20000 . forAll policies $ \pol ->
      forAll ((,) <$> chooseEnum (minBound, maxBound) <*> types) $ \(op, t) ->
        forAll ((,) <$> valueFor t <*> valueFor t) $ \(a, b) ->
          let Binary f = binaryOn pol op t t
           in counterexample (show (op, t, a, b)) (show (f a b) === show (binary pol op a b))
  it "storeOn keeps what fitWhy keeps" $
    withMaxSuccess 20000 . forAll policies $ \pol ->
      forAll types $ \t ->
        forAll (valueFor t) $ \v ->
          counterexample (show (t, v)) (show (storing (storeOn pol t) v) === show (fst (fitWhy pol t v)))
  it "convertOn gives convert's outcome" $
    withMaxSuccess 20000 . forAll policies $ \pol ->
      forAll ((,) <$> types <*> types) $ \(from, to) ->
        forAll (valueFor from) $ \v ->
          let Convert f = convertOn pol from to
           in counterexample (show (from, to, v)) (show (f v) === show (convert pol from to v))
  it "computes on the machine's integers where it can, and gives the policies' outcome where the result leaves the type" $ do
    let Binary add = binaryOn tecomat BAdd (TElem INT) (TElem INT)
    add (VInt INT 2) (VInt INT 3) `shouldBe` Right (VInt INT 5)
    add (VInt INT 32767) (VInt INT 1) `shouldBe` binary tecomat BAdd (VInt INT 32767) (VInt INT 1)
    add (VInt INT 32767) (VInt INT 1) `shouldNotBe` Right (VInt INT 32768)
