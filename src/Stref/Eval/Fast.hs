-- | Fast paths of the operators for the common operand types, with exactly
-- the results of "Stref.Operators" and "Stref.Conversions" (the reference;
-- test/FastSpec.hs checks the equality on random values under every
-- policy). All integer types are at most 32 bits wide, so every exact
-- result of + - * DIV MOD on INT, DINT and USINT fits a 64-bit 'Int' and no
-- 'Integer' is needed. Everything else (bit strings, which the reference
-- rejects for arithmetic, MT-OP-5) goes to the reference.
module Stref.Eval.Fast
  ( arithFast
  , compareFast
  , convertFast
  , valueToInt
  , intToValue
  ) where

import Data.Int (Int16, Int32)
import Data.Word (Word16, Word8)
import Stref.Checked (ArithOp (..), CmpOp (..))
import Stref.Conversions (convert)
import Stref.Diagnostics
import Stref.Numeric (isRealInfinite, isRealNaN, realMax)
import qualified Stref.Operators as O
import Stref.Policy
import Stref.Types
import Stref.Values

-- | 'O.arith' with the policy and operator fixed once (MT-OP-4..10).
arithFast :: Policies -> ArithOp -> Value -> Value -> O.Outcome
arithFast p op = \a b -> case (a, b) of
  (VInt x, VInt y) -> onInt (fromIntegral x) (fromIntegral y)
  (VDInt x, VDInt y) -> onDInt (fromIntegral x) (fromIntegral y)
  (VReal x, VReal y) -> realArith p op x y
  (VUSInt x, VUSInt y) -> onUSInt (fromIntegral x) (fromIntegral y)
  _ -> O.arith p op a b
  where
    -- the operation on each type, chosen once
    onInt = intArith p op INT (\r -> VInt (fromIntegral r))
    onDInt = intArith p op DINT (\r -> VDInt (fromIntegral r))
    onUSInt = intArith p op USINT (\r -> VUSInt (fromIntegral r))

-- | 'Stref.Operators' intArith on 'Int' (the same case analysis), with the
-- operator, type and policies fixed once.
intArith :: Policies -> ArithOp -> BasicType -> (Int -> Value) -> Int -> Int -> O.Outcome
intArith p op t mk = case op of
  OpAdd -> \x y -> setsFlag (x + y)
  OpSub -> \x y -> setsFlag (x - y)
  OpMul -> \x y -> setsFlag (x * y)
  OpDiv -> \x y ->
    if y == 0
      then case pDivZero p of
        DivZeroError -> Left errDivisionByZero -- MT-OP-9, MT-ERR-2020
        DivZeroZero -> Right (mk 0, Nothing)
        DivZeroTrap -> Left trapDivisionByZero
      else keepsFlag (divide (pModSign p) x y) -- MT-OP-10, A7
  OpMod -> \x y ->
    if y == 0
      then case pModZero p of
        ModZeroZero -> Right (mk 0, Nothing) -- MT-OP-8
        ModZeroError -> Left errModZero
      else keepsFlag (modulo (pModSign p) x y)
  where
    (lo, hi) = range t
    (wl, wh) = case pArithWidth p of
      OperandType -> (lo, hi)
      Promote32 -> (dintLo, dintHi)
    -- MT-OP-7: + - * set the flag to whether the result overflowed
    setsFlag exact
      | wl <= exact && exact <= wh = Right (mk (narrow exact), Just False)
      | otherwise = case pOverflow p of
          Saturate -> Right (mk (narrow (max wl (min wh exact))), Just True) -- MT-OP-6
          Wrap -> Right (mk (narrow (wrapIn wl wh exact)), Just True)
          Trap -> Left trapOverflow
    keepsFlag exact
      | wl <= exact && exact <= wh = Right (mk (narrow exact), Nothing)
      | otherwise = case pOverflow p of
          Saturate -> Right (mk (narrow (max wl (min wh exact))), Nothing)
          Wrap -> Right (mk (narrow (wrapIn wl wh exact)), Nothing)
          Trap -> Left trapOverflow
    -- under promote-32 the 32-bit result is narrowed to the type like an
    -- integer narrowing conversion (the identity under operand-type)
    narrow = case pArithWidth p of
      OperandType -> id
      Promote32 -> case pNarrowInt p of
        NarrowWrap -> wrapIn lo hi
        NarrowSaturate -> \r -> max lo (min hi r)

wrapIn :: Int -> Int -> Int -> Int
wrapIn lo hi x = lo + (x - lo) `mod` (hi - lo + 1)

dintLo, dintHi :: Int
dintLo = -2147483648
dintHi = 2147483647

range :: BasicType -> (Int, Int)
range = \case
  USINT -> (0, 255)
  BYTE -> (0, 255)
  INT -> (-32768, 32767)
  WORD -> (0, 65535)
  DINT -> (dintLo, dintHi)
  _ -> (0, 0) -- never asked: the other types do not come here

divide :: ModSign -> Int -> Int -> Int
divide ModSignDividend x y = x `quot` y
divide ModSignEuclidean x y = (x - modulo ModSignEuclidean x y) `div` y

modulo :: ModSign -> Int -> Int -> Int
modulo ModSignDividend x y = x `rem` y
modulo ModSignEuclidean x y = x `mod` abs y

-- | 'Stref.Operators' realArith without the operand lists (A6).
realArith :: Policies -> ArithOp -> Float -> Float -> O.Outcome
realArith p op x y = case op of
  OpAdd -> setsFlag (x + y)
  OpSub -> setsFlag (x - y)
  OpMul -> setsFlag (x * y)
  OpDiv
    | y == 0 -> case pRealDivZero p of
        RealDivZeroError -> Left errDivisionByZero -- A6, MT-OP-9
        RealDivZeroIeee -> Right (VReal (x / y), Nothing)
    | otherwise -> Right (VReal (fst (overflow (x / y))), Nothing)
  OpMod -> Left errOperandTypes
  where
    setsFlag r = let (r', o) = overflow r in Right (VReal r', Just o)
    overflow r
      | isRealInfinite r && not (isRealInfinite x || isRealInfinite y || isRealNaN x || isRealNaN y) =
          case pRealOverflow p of
            RealOverflowSaturate -> (if r > 0 then realMax else negate realMax, True)
            RealOverflowIeee -> (r, True)
      | otherwise = (r, False)

-- | 'O.compareValues' with the operator fixed once (MT-OP-11).
compareFast :: CmpOp -> Value -> Value -> Bool
compareFast op = case op of
  OpLt -> go (<) (<)
  OpGt -> go (>) (>)
  OpLe -> go (<=) (<=)
  OpGe -> go (>=) (>=)
  OpEq -> go (==) (==)
  OpNe -> go (/=) (/=)
  where
    go :: (Int -> Int -> Bool) -> (Float -> Float -> Bool) -> Value -> Value -> Bool
    go cmpI cmpR a b = case (a, b) of
      (VInt x, VInt y) -> cmpI (fromIntegral x) (fromIntegral y)
      (VDInt x, VDInt y) -> cmpI (fromIntegral x) (fromIntegral y)
      (VReal x, VReal y) -> cmpR x y
      (VBool x, VBool y) -> cmpI (fromEnum x) (fromEnum y)
      (VUSInt x, VUSInt y) -> cmpI (fromIntegral x) (fromIntegral y)
      (VWord x, VWord y) -> cmpI (fromIntegral x) (fromIntegral y)
      (VByte x, VByte y) -> cmpI (fromIntegral x) (fromIntegral y)
      (VDWord x, VDWord y) -> cmpI (fromIntegral x) (fromIntegral y)
      _ -> O.compareValues op a b
{-# INLINE compareFast #-}

-- | 'convert' with the two types fixed once: the conversions between INT,
-- DINT, USINT and REAL that need no rounding or narrowing policy directly,
-- the rest through the reference (MT-CONV-5, Table 4-6).
convertFast :: Policies -> BasicType -> BasicType -> Value -> Value
convertFast p from to = case (from, to) of
  _ | from == to -> id
  (INT, DINT) -> \case VInt x -> VDInt (fromIntegral x); v -> ref v -- C40: sign-extended
  (USINT, INT) -> \case VUSInt x -> VInt (fromIntegral x); v -> ref v
  (USINT, DINT) -> \case VUSInt x -> VDInt (fromIntegral x); v -> ref v
  (INT, REAL) -> \case VInt x -> VReal (fromIntegral x); v -> ref v -- exact: |x| < 2^24
  (USINT, REAL) -> \case VUSInt x -> VReal (fromIntegral x); v -> ref v
  (BYTE, WORD) -> \case VByte x -> VWord (fromIntegral x); v -> ref v
  (DINT, INT) -> narrowTo INT (\x -> VInt (fromIntegral x :: Int16))
  (DINT, BYTE) -> narrowTo BYTE (\x -> VByte (fromIntegral x :: Word8))
  (DINT, WORD) -> narrowTo WORD (\x -> VWord (fromIntegral x :: Word16))
  _ -> ref
  where
    ref = convert p from to
    -- a narrower target: the low bits, or the nearest value under
    -- narrow-int=saturate (C16, C17, C44-C47)
    narrowTo t mk = case pNarrowInt p of
      NarrowWrap -> \case VDInt x -> mk (fromIntegral x :: Int); v -> ref v
      NarrowSaturate -> \case VDInt x -> let (l, h) = range t in mk (max l (min h (fromIntegral (x :: Int32)))); v -> ref v

-- | The number of an integer value without 'Integer' ('valueToInteger' for
-- every type but REAL; all fit an 'Int').
valueToInt :: Value -> Maybe Int
valueToInt = \case
  VInt i -> Just (fromIntegral i)
  VDInt i -> Just (fromIntegral i)
  VUSInt w -> Just (fromIntegral w)
  VBool b -> Just (if b then 1 else 0)
  VByte w -> Just (fromIntegral w)
  VWord w -> Just (fromIntegral w)
  VDWord w -> Just (fromIntegral w)
  VReal _ -> Nothing
{-# INLINE valueToInt #-}

-- | 'integerToValue' from an 'Int' (the same low bits; REAL by the nearest
-- binary32 through the reference).
intToValue :: BasicType -> Int -> Value
intToValue t n = case t of
  INT -> VInt (fromIntegral n)
  DINT -> VDInt (fromIntegral n)
  USINT -> VUSInt (fromIntegral n)
  BYTE -> VByte (fromIntegral n)
  WORD -> VWord (fromIntegral n)
  DWORD -> VDWord (fromIntegral n)
  BOOL -> VBool (n /= 0)
  REAL -> integerToValue REAL (toInteger n)
