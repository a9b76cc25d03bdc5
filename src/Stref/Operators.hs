{-# OPTIONS_GHC -O2 #-}
-- (the interpreter's hot path: bench/RESULTS.md measures -O2 against -O1)
-- | Operators (catalogue §5, Tables 4-10 to 4-13) and EXPT (MT-OP-20): the
-- meaning of each operator on values, under the policies. docs/numeric.md
-- explains every choice.
--
-- Operands already have their common type (the checker inserted the
-- conversions). A result is either a runtime error code (the interpreter
-- adds the line) or a value with the effect on INTERNAL_OVERFLOW: @Just b@
-- sets the flag to @b@ (+, -, *, unary -, EXPT; MT-OP-7), 'Nothing' leaves it.
-- Operands of types the checker rejects (MOD on REAL, unary minus on USINT,
-- two different types) give 'errOperandTypes', never a crash.
module Stref.Operators
  ( Outcome
  , arith
  , negateValue
  , notValue
  , compareValues
  , logic
  , expt
  , realArithWith
  , divide
  , modulo
  ) where

import Data.Bits (complement, xor, (.&.), (.|.))
import Stref.Checked (ArithOp (..), CmpOp (..), LogicOp (..))
import Stref.Diagnostics
import Stref.Numeric
import Stref.Policy
import Stref.Types
import Stref.Values

type Outcome = Either ErrorCode (Value, Maybe Bool)

-- | Binary arithmetic (MT-OP-4): both operands of one ANY_NUM type, the
-- result of that type.
arith :: Policies -> ArithOp -> Value -> Value -> Outcome
arith p op a b = case (a, b) of
  (VReal x, VReal y) -> realArith p op x y
  _
    | valueType a == valueType b
    , isAnyInt (valueType a)
    , Just x <- valueToInteger a
    , Just y <- valueToInteger b ->
        intArith p op (valueType a) x y
    | otherwise -> Left errOperandTypes

intArith :: Policies -> ArithOp -> BasicType -> Integer -> Integer -> Outcome
intArith p op t x y = case op of
  OpAdd -> setsFlag (store p t (x + y))
  OpSub -> setsFlag (store p t (x - y))
  OpMul -> setsFlag (store p t (x * y))
  OpDiv
    | y == 0 -> case pDivZero p of
        DivZeroError -> Left errDivisionByZero -- MT-OP-9, MT-ERR-2020
        DivZeroZero -> Right (defaultValue t, Nothing)
        DivZeroTrap -> Left trapDivisionByZero
    -- MT-OP-10, A7: only -32768 / -1 (and its DINT twin) leaves the range;
    -- the overflow policy picks the value, the flag stays (MT-OP-7).
    | otherwise -> keepsFlag (store p t (divide (pModSign p) x y))
  OpMod
    | y == 0 -> case pModZero p of
        ModZeroZero -> Right (defaultValue t, Nothing) -- MT-OP-8
        ModZeroError -> Left errModZero
    | otherwise -> keepsFlag (store p t (modulo (pModSign p) x y))
  where
    setsFlag = fmap (\(v, o) -> (v, Just o)) -- MT-OP-7
    keepsFlag = fmap (\(v, _) -> (v, Nothing))

-- | Quotient: truncated toward zero (A7, MT-OP-10) or euclidean (the
-- remainder is never negative).
-- (On 'Integer' here, on 'Int' in the interpreter's fast path.)
divide :: Integral a => ModSign -> a -> a -> a
divide ModSignDividend x y = x `quot` y
divide ModSignEuclidean x y = (x - modulo ModSignEuclidean x y) `div` y
{-# INLINE divide #-}

-- | Remainder: the sign of the dividend (A7) or euclidean (0 <= r < |y|).
-- In both cases x = y * divide x y + modulo x y.
modulo :: Integral a => ModSign -> a -> a -> a
modulo ModSignDividend x y = x `rem` y
modulo ModSignEuclidean x y = x `mod` abs y
{-# INLINE modulo #-}

-- | The value stored for an exact integer result of type @t@, and whether the
-- arithmetic overflowed. Under @operand-type@ the arithmetic has the width of
-- @t@ (MT-OP-4) and the overflow policy applies to its range (MT-OP-6).
-- Under @promote-32@ it is done on 32-bit signed integers (DINT): the overflow
-- policy applies to the DINT range, and the 32-bit result is then narrowed to
-- @t@ the way an integer narrowing conversion is (the @narrow-int@ policy),
-- which never reports an overflow.
store :: Policies -> BasicType -> Integer -> Either ErrorCode (Value, Bool)
store p t exact = case pArithWidth p of
  OperandType -> do
    (x, o) <- overflowIn t
    pure (integerToValue t x, o)
  Promote32 -> do
    (x, o) <- overflowIn DINT
    pure (integerToValue t (narrowInteger (pNarrowInt p) t x), o)
  where
    overflowIn w
      | fitsIn w exact = Right (exact, False)
      | otherwise = case pOverflow p of
          Saturate -> Right (clampTo w exact, True) -- MT-OP-6
          Wrap -> Right (wrapTo w exact, True)
          Trap -> Left trapOverflow

narrowInteger :: NarrowInt -> BasicType -> Integer -> Integer
narrowInteger NarrowWrap t = wrapTo t
narrowInteger NarrowSaturate t = clampTo t

-- | REAL arithmetic, every operation rounded once to binary32 (Haskell
-- 'Float' arithmetic is single precision).
realArith :: Policies -> ArithOp -> Float -> Float -> Outcome
realArith = realArithWith (\r o -> Right (VReal r, Just o)) (\r -> Right (VReal r, Nothing)) Left

-- | 'realArith' with the three kinds of result given as functions (a value
-- that sets INTERNAL_OVERFLOW, a value that leaves it, an error), so that
-- the interpreter's fast path shares this definition without building an
-- 'Outcome'.
realArithWith :: (Float -> Bool -> r) -> (Float -> r) -> (ErrorCode -> r) -> Policies -> ArithOp -> Float -> Float -> r
realArithWith flagged plain failed p op x y = case op of
  OpAdd -> setsFlag (x + y)
  OpSub -> setsFlag (x - y)
  OpMul -> setsFlag (x * y)
  OpDiv
    | y == 0 -> case pRealDivZero p of
        RealDivZeroError -> failed errDivisionByZero -- A6, MT-OP-9
        RealDivZeroIeee -> plain (x / y)
    | otherwise -> plain (fst (realOverflow p finite (x / y)))
  OpMod -> failed errOperandTypes -- MT-OP-5: MOD is ANY_INT only
  where
    finite = not (isRealInfinite x || isRealInfinite y || isRealNaN x || isRealNaN y)
    setsFlag r = let (r', o) = realOverflow p finite r in flagged r' o
{-# INLINE realArithWith #-}

-- | A6: a REAL result overflows when finite operands give an infinity. The
-- overflow is reported (the flag) under both alternatives; @saturate@
-- replaces the infinity by the largest finite binary32 of its sign, @ieee@
-- keeps it. Infinite or NaN operands (@finite@ is False) propagate by IEEE
-- rules and are not an overflow of this operation.
realOverflow :: Policies -> Bool -> Float -> (Float, Bool)
realOverflow p finite r
  | isRealInfinite r && finite =
      case pRealOverflow p of
        RealOverflowSaturate -> (if r > 0 then realMax else negate realMax, True)
        RealOverflowIeee -> (r, True)
  | otherwise = (r, False)
{-# INLINE realOverflow #-}

-- | Unary minus (MT-OP-4, MT-OP-5): INT, DINT and REAL only. @-(-32768)@ is
-- an overflow of INT (MT-OP-6). REAL negation only flips the sign.
negateValue :: Policies -> Value -> Outcome
negateValue p v = case v of
  VReal x -> Right (VReal (negate x), Just False)
  VInt x -> intNegate INT (toInteger x)
  VDInt x -> intNegate DINT (toInteger x)
  _ -> Left errOperandTypes
  where
    intNegate t x = (\(r, o) -> (r, Just o)) <$> store p t (negate x) -- MT-OP-7

-- | NOT (MT-OP-14): complement of a BOOL, bitwise complement of a BYTE, WORD
-- or DWORD. Other types (rejected by the checker, MT-OP-15) are returned
-- unchanged.
notValue :: Value -> Value
notValue = \case
  VBool b -> VBool (not b)
  VByte w -> VByte (complement w)
  VWord w -> VWord (complement w)
  VDWord w -> VDWord (complement w)
  v -> v

-- | Relational operators (MT-OP-11). REAL compares by IEEE rules: @-0.0 =
-- 0.0@, and a NaN makes every comparison FALSE except @<>@, which is TRUE.
-- Integers compare by value, bit strings as unsigned numbers (MT-TYPE-2),
-- FALSE < TRUE. Operands of different types (never after checking) are
-- unequal and unordered.
compareValues :: CmpOp -> Value -> Value -> Bool
compareValues op a b = case (a, b) of
  (VReal x, VReal y) -> cmp x y
  _
    | valueType a == valueType b
    , Just x <- valueToInteger a
    , Just y <- valueToInteger b ->
        cmp x y
    | otherwise -> op == OpNe
  where
    cmp :: Ord n => n -> n -> Bool
    cmp x y = case op of
      OpLt -> x < y
      OpGt -> x > y
      OpLe -> x <= y
      OpGe -> x >= y
      OpEq -> x == y
      OpNe -> not (x == y)

-- | AND, OR, XOR (MT-OP-12..14): boolean logic on BOOL (Table 4-12), bit by
-- bit on BYTE, WORD, DWORD. Other combinations (rejected by the checker,
-- MT-OP-15) return the left operand.
logic :: LogicOp -> Value -> Value -> Value
logic op a b = case (a, b) of
  (VBool x, VBool y) -> VBool (boolOp x y)
  (VByte x, VByte y) -> VByte (bitOp x y)
  (VWord x, VWord y) -> VWord (bitOp x y)
  (VDWord x, VDWord y) -> VDWord (bitOp x y)
  _ -> a
  where
    boolOp x y = case op of
      OpAnd -> x && y
      OpOr -> x || y
      OpXor -> x /= y
    bitOp x y = case op of
      OpAnd -> x .&. y
      OpOr -> x .|. y
      OpXor -> x `xor` y

-- | EXPT(base, exponent) (MT-OP-20): base USINT, INT, DINT or REAL, exponent
-- USINT, result of the base's type; EXPT(x, 0) = 1 for every x. Integer
-- powers are computed exactly, then stored like the result of * (overflow
-- policy, flag). REAL powers are computed exactly from the binary32 base and
-- rounded once to binary32, then an overflow is handled like that of *.
expt :: Policies -> Value -> Value -> Outcome
expt p base ex = case (base, ex) of
  (VReal x, VUSInt e) -> Right (realExpt p x (toInteger e))
  (_, VUSInt e)
    | isAnyInt (valueType base)
    , Just x <- valueToInteger base ->
        (\(r, o) -> (r, Just o)) <$> store p (valueType base) (x ^ e)
  _ -> Left errOperandTypes

realExpt :: Policies -> Float -> Integer -> (Value, Maybe Bool)
realExpt p x e
  | e == 0 = (VReal 1, Just False)
  | otherwise = case realToRational x of
      Nothing
        | isRealNaN x -> (VReal x, Just False)
        | otherwise -> (VReal (if x < 0 && odd e then negate realInfinity else realInfinity), Just False)
      Just q
        | q == 0 -> (VReal (if isNegativeZero x && odd e then -0.0 else 0), Just False)
        | otherwise ->
            let (r, o) = realOverflow p True (roundToReal (q ^ e))
             in (VReal r, Just o)
