-- | A deliberately naive evaluator of typed expressions, written from the
-- catalogue for clarity, not speed: every integer operation is done on
-- exact 'Integer's and then clamped (or wrapped), every REAL operation on
-- exact 'Rational's and then rounded once to binary32. It is the second
-- opinion in the law "two evaluators agree" (test/LawsSpec.hs).
--
-- It follows the MasterTool preset, with the @overflow@ policy as a
-- parameter. Function calls are outside its scope ('Nothing').
module Stref.Explore.Naive
  ( naiveEval
  , naiveConvert
  ) where

import qualified Data.Map.Strict as M
import Data.Text (Text)
import Stref.Checked (ArithOp (..), CmpOp (..), LogicOp (..))
import Stref.Generate.Program (TExpr (..), litValue)
import Stref.Policy (Overflow (..))
import Stref.Types
import Stref.Values

-- | Value and INTERNAL_OVERFLOW after the expression, or a runtime error
-- code. Operands are evaluated left to right (decision A18).
naiveEval :: Overflow -> M.Map Text Value -> Bool -> TExpr -> Maybe (Either Int (Value, Bool))
naiveEval ovf env = go
  where
    go flag = \case
      TLit t l -> ok (litValue t l) flag
      TVar _ v -> (\x -> Right (x, flag)) <$> M.lookup v env
      TFlag -> ok (VBool flag) flag
      TWiden _ t e -> fmap (\(x, f) -> (naiveConvert t x, f)) <$> go flag e
      TConv _ t e -> fmap (\(x, f) -> (naiveConvert t x, f)) <$> go flag e -- MT-CONV-14: no flag change
      TNeg _ e -> bind (go flag e) $ \x _ -> case x of
        VReal r -> ok (VReal (negate r)) False -- a sign flip, never an overflow
        _ -> intResult True (valueType x) (negate (int x))
      TNot _ e -> bind (go flag e) $ \x f -> ok (complementOf x) f
      TArith op t a b -> bind2 a b flag $ \x y f -> arith op t x y f
      TCmp op _ a b -> bind2 a b flag $ \x y f -> ok (VBool (compareBy op (number x) (number y))) f
      TLogic op t a b -> bind2 a b flag $ \x y f -> ok (bitwise op t x y) f
      TExpt t a b -> bind2 a b flag $ \x y _ -> case x of
        VReal r -> realResult True (if int y == 0 then 1 else toRational r ^ int y) (signOfPower r (int y)) -- MT-OP-20
        _ -> intResult True t (int x ^ int y)
      TCall {} -> Nothing
      TIndex {} -> Nothing
    ok v f = Just (Right (v, f))
    bind m k = m >>= either (Just . Left) (uncurry k)
    bind2 a b flag k = bind (go flag a) $ \x f1 -> bind (go f1 b) $ \y f2 -> k x y f2

    -- MT-OP-4, MT-OP-6..10, A6, A7.
    arith op t x y flag = case (x, y) of
      (VReal r, VReal s) -> case op of
        OpAdd -> realResult True (toRational r + toRational s) (sumSign r s)
        OpSub -> realResult True (toRational r - toRational s) (sumSign r (negate s))
        OpMul -> realResult True (toRational r * toRational s) (productSign r s)
        OpDiv
          | s == 0 -> Just (Left 2020)
          | otherwise -> realResult False (toRational r / toRational s) (productSign r s) >>= keepFlag
        OpMod -> Nothing
      _ -> case op of
        OpAdd -> intResult True t (int x + int y)
        OpSub -> intResult True t (int x - int y)
        OpMul -> intResult True t (int x * int y)
        OpDiv
          | int y == 0 -> Just (Left 2020) -- MT-OP-9
          | otherwise -> intResult False t (int x `quot` int y) >>= keepFlag -- A7, MT-OP-10
        OpMod
          | int y == 0 -> ok (integerToValue t 0) flag -- MT-OP-8
          | otherwise -> ok (integerToValue t (int x `rem` int y)) flag
      where
        keepFlag = \case
          Right (v, _) -> Just (Right (v, flag))
          Left e -> Just (Left e)

    -- An exact integer result stored in type t (MT-OP-6 and the policy).
    intResult setsFlag t exact
      | exact >= lo && exact <= hi = ok (integerToValue t exact) False
      | otherwise = case ovf of
          Saturate -> ok (integerToValue t (max lo (min hi exact))) setsFlag
          Wrap -> ok (integerToValue t (lo + (exact - lo) `mod` (hi - lo + 1))) setsFlag
          Trap -> Just (Left 9001)
      where
        (lo, hi) = maybe (0, 0) id (intRange t)

    -- An exact REAL result rounded once; beyond the range it saturates at
    -- the largest binary32 and raises the flag (A6). A zero takes the IEEE
    -- sign given by the caller.
    realResult _ exact zeroSign
      | exact == 0 = ok (VReal (if zeroSign then -0.0 else 0)) False
      | isInfinite rounded = ok (VReal (if exact > 0 then maxReal else negate maxReal)) True
      | otherwise = ok (VReal rounded) False
      where
        rounded = fromRational exact :: Float
    maxReal = 3.4028235e38 :: Float

    -- IEEE 754 signs of zero results under round-to-nearest.
    sumSign r s = isNegZero r && isNegZero s
    productSign r s = (r < 0 || isNegZero r) /= (s < 0 || isNegZero s)
    signOfPower r e = (r < 0 || isNegZero r) && odd e
    isNegZero r = isNegativeZero r

    int v = maybe 0 id (valueToInteger v)
    number v = case v of
      VReal r -> toRational r
      _ -> fromInteger (int v)
    compareBy op = case op of
      OpLt -> (<)
      OpGt -> (>)
      OpLe -> (<=)
      OpGe -> (>=)
      OpEq -> (==)
      OpNe -> (/=)
    bits t = maybe 1 (\(_, hi) -> hi + 1) (intRange t)
    complementOf v = case v of
      VBool b -> VBool (not b)
      _ -> integerToValue (valueType v) (bits (valueType v) - 1 - int v)
    bitwise op t x y = case (x, y) of
      (VBool a, VBool b) -> VBool (case op of OpAnd -> a && b; OpOr -> a || b; OpXor -> a /= b)
      _ -> integerToValue t (bitByBit op (int x) (int y))
    bitByBit op a b
      | a == 0 && b == 0 = 0
      | otherwise =
          let low = case op of
                OpAnd -> (a `mod` 2) * (b `mod` 2)
                OpOr -> max (a `mod` 2) (b `mod` 2)
                OpXor -> (a + b) `mod` 2
           in low + 2 * bitByBit op (a `div` 2) (b `div` 2)

-- | Table 4-6 read directly: the numeric value of the source (bit strings
-- unsigned, BOOL 0/1, REAL truncated toward zero and saturated at the
-- target's limits, or at DINT's for WORD, C51-C53), then the target: BOOL is
-- "not zero", REAL the nearest binary32, every other type the low bits.
naiveConvert :: BasicType -> Value -> Value
naiveConvert target v = case (v, target) of
  (VReal r, BOOL) -> VBool (r /= 0) -- C50
  (VReal r, REAL) -> VReal r
  (VReal r, INT) -> integerToValue INT (clampTo INT (truncate r)) -- C52
  (VReal r, _) -> naiveConvert target (integerToValue DINT (clampTo DINT (truncate r))) -- C51, C53
  (_, BOOL) -> VBool (n /= 0)
  (_, REAL) -> VReal (fromRational (fromInteger n))
  _ -> integerToValue target n -- the low bits (integerToValue keeps them)
  where
    n = maybe 0 id (valueToInteger v)
    clampTo t x = let (lo, hi) = maybe (0, 0) id (intRange t) in max lo (min hi x)
