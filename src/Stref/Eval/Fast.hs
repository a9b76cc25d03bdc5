{-# OPTIONS_GHC -O2 #-}
-- (the interpreter's hot path: bench/RESULTS.md measures -O2 against -O1)
-- | Fast paths of the operators for the common operand types, with exactly
-- the results of "Stref.Operators" and "Stref.Conversions" (the reference;
-- test/FastSpec.hs checks the equality on random values under every
-- policy). All integer types are at most 32 bits wide, so every exact
-- result of + - * DIV MOD on INT, DINT and USINT fits a 64-bit 'Int' and no
-- 'Integer' is needed. Everything else (bit strings, which the reference
-- rejects for arithmetic, MT-OP-5) goes to the reference.
--
-- Each function does its case analysis on the policies, operator and types
-- once and returns the remaining work as a closure inside a strict data
-- constructor ('Binary', 'Unary'): the constructor keeps GHC from pushing
-- that analysis back into the closure, which would redo it on every
-- operation. Results are the strict 'Result', so no lazy pair is built.
module Stref.Eval.Fast
  ( Result (..)
  , resultOutcome
  , fromOutcome
  , Binary (..)
  , Unary (..)
  , arithFast
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
import qualified Stref.Operators as O
import Stref.Policy
import Stref.Types
import Stref.Values

-- | An operator's result: a value that sets INTERNAL_OVERFLOW to the given
-- state (MT-OP-7), a value that leaves it, or a runtime error.
data Result
  = Flagged !Value !Bool
  | Plain !Value
  | Raised !ErrorCode
  deriving (Eq, Show)

-- | The reference's form of a result.
resultOutcome :: Result -> O.Outcome
resultOutcome = \case
  Flagged v o -> Right (v, Just o)
  Plain v -> Right (v, Nothing)
  Raised c -> Left c

fromOutcome :: O.Outcome -> Result
fromOutcome = \case
  Right (v, Just o) -> Flagged v o
  Right (v, Nothing) -> Plain v
  Left c -> Raised c

-- | A binary operation with everything but its operands fixed.
data Binary a = Binary !(Value -> Value -> a)

-- | A unary operation with everything but its operand fixed.
data Unary a = Unary !(Value -> a)

-- | 'O.arith' with the policy, the operator and the operands' type (the
-- checker's) fixed once (MT-OP-4..10). Operands of another type go to the
-- reference, which rejects them.
arithFast :: Policies -> ArithOp -> BasicType -> Binary Result
arithFast p op t = case t of
  INT -> intArith p op INT (\r -> VInt (fromIntegral r)) $ \f -> Binary $ \a b -> case (a, b) of
    (VInt x, VInt y) -> f (fromIntegral x) (fromIntegral y)
    _ -> reference a b
  DINT -> intArith p op DINT (\r -> VDInt (fromIntegral r)) $ \f -> Binary $ \a b -> case (a, b) of
    (VDInt x, VDInt y) -> f (fromIntegral x) (fromIntegral y)
    _ -> reference a b
  USINT -> intArith p op USINT (\r -> VUSInt (fromIntegral r)) $ \f -> Binary $ \a b -> case (a, b) of
    (VUSInt x, VUSInt y) -> f (fromIntegral x) (fromIntegral y)
    _ -> reference a b
  REAL -> realArith op $ \f -> Binary $ \a b -> case (a, b) of
    (VReal x, VReal y) -> f x y
    _ -> reference a b
  _ -> Binary reference
  where
    reference a b = fromOutcome (O.arith p op a b)
    -- the operator chosen here, so that each closure holds the code of one
    -- operator only
    realArith o lift = case o of
      OpAdd -> lift (onReal OpAdd)
      OpSub -> lift (onReal OpSub)
      OpMul -> lift (onReal OpMul)
      OpDiv -> lift (onReal OpDiv)
      OpMod -> lift (onReal OpMod)
    onReal = O.realArithWith (\r o -> Flagged (VReal r) o) (Plain . VReal) Raised p
    {-# INLINE realArith #-}

-- | 'Stref.Operators' intArith on 'Int' (the same case analysis), with the
-- operator, type and policies fixed once; @lift@ receives the operation of
-- the chosen operator (inlined, so that it is one closure without calls).
intArith :: Policies -> ArithOp -> BasicType -> (Int -> Value) -> ((Int -> Int -> Result) -> r) -> r
intArith p op t mk lift = case op of
  OpAdd -> lift $ \x y -> setsFlag (x + y)
  OpSub -> lift $ \x y -> setsFlag (x - y)
  OpMul -> lift $ \x y -> setsFlag (x * y)
  OpDiv -> lift $ \x y ->
    if y == 0
      then case divZero of
        DivZeroError -> Raised errDivisionByZero -- MT-OP-9, MT-ERR-2020
        DivZeroZero -> Plain (mk 0)
        DivZeroTrap -> Raised trapDivisionByZero
      else keepsFlag (O.divide modSign x y) -- MT-OP-10, A7
  OpMod -> lift $ \x y ->
    if y == 0
      then case modZero of
        ModZeroZero -> Plain (mk 0) -- MT-OP-8
        ModZeroError -> Raised errModZero
      else keepsFlag (O.modulo modSign x y)
  where
    !divZero = pDivZero p
    !modZero = pModZero p
    !modSign = pModSign p
    !overflow = pOverflow p
    !(lo, hi) = range t
    !(wl, wh) = case pArithWidth p of
      OperandType -> (lo, hi)
      Promote32 -> (dintLo, dintHi)
    -- MT-OP-7: + - * set the flag to whether the result overflowed
    setsFlag !exact
      | wl <= exact && exact <= wh = Flagged (mk $! narrow exact) False
      | otherwise = case overflow of
          Saturate -> Flagged (mk $! narrow (max wl (min wh exact))) True -- MT-OP-6
          Wrap -> Flagged (mk $! narrow (wrapIn wl wh exact)) True
          Trap -> Raised trapOverflow
    {-# INLINE setsFlag #-}
    keepsFlag !exact
      | wl <= exact && exact <= wh = Plain (mk $! narrow exact)
      | otherwise = case overflow of
          Saturate -> Plain (mk $! narrow (max wl (min wh exact)))
          Wrap -> Plain (mk $! narrow (wrapIn wl wh exact))
          Trap -> Raised trapOverflow
    {-# INLINE keepsFlag #-}
    -- under promote-32 the 32-bit result is narrowed to the type like an
    -- integer narrowing conversion (the identity under operand-type)
    !promoted = case pArithWidth p of
      OperandType -> False
      Promote32 -> True
    !narrowSaturates = case pNarrowInt p of
      NarrowWrap -> False
      NarrowSaturate -> True
    narrow r
      | not promoted = r
      | narrowSaturates = max lo (min hi r)
      | otherwise = wrapIn lo hi r

{-# INLINE intArith #-}

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

-- | 'O.compareValues' with the operator fixed once (MT-OP-11).
compareFast :: CmpOp -> Binary Bool
compareFast op = Binary $ case op of
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

-- | 'convert' with the two types fixed once: the conversions between INT,
-- DINT, USINT and REAL that need no rounding or narrowing policy directly,
-- the rest through the reference (MT-CONV-5, Table 4-6).
convertFast :: Policies -> BasicType -> BasicType -> Unary Value
convertFast p from to = Unary $ case (from, to) of
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
  (REAL, DINT) -> realTo DINT (\x -> VDInt (fromIntegral x))
  (REAL, INT) -> realTo INT (\x -> VInt (fromIntegral x))
  _ -> ref
  where
    ref = convert p from to
    -- C52, C53 under the saturating policies for a REAL of magnitude below
    -- 2^31, where truncate and round on machine integers are exact (GHC's
    -- round breaks ties to even, as MT-CONV-9 asks); NaN, infinities and
    -- larger values go to the reference
    realTo t mk = case pRealToInt p of
      TruncateSaturate -> \case VReal r | abs r < 2147483648 -> mk (clamp t (truncate r)); v -> ref v
      RoundEvenSaturate -> \case VReal r | abs r < 2147483648 -> mk (clamp t (round r)); v -> ref v
      RoundEvenWrap -> ref
    clamp t x = let (l, h) = range t in max l (min h x)
    -- a narrower target: the low bits, or the nearest value under
    -- narrow-int=saturate (C16, C17, C44-C47)
    narrowTo t mk = case pNarrowInt p of
      NarrowWrap -> \case VDInt x -> mk (fromIntegral x :: Int); v -> ref v
      NarrowSaturate -> \case VDInt x -> let (l, h) = range t in mk (max l (min h (fromIntegral (x :: Int32)))); v -> ref v

