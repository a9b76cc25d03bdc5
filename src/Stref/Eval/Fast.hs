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
  , IntArith
  , intArith
  , intOp
  , arithCanFail
  , eachArithOp
  , eachCmpOp
  , cmpWith
  , eachIntBox
  , eachPatternNumber
  , range
  , compareFast
  , convertFast
  , valueToInt
  , intToValue
  ) where

import Data.Int (Int16, Int32)
import Data.Word (Word16, Word32, Word8)
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
  INT -> intArithValues INT (\case VInt x -> Just (fromIntegral x); _ -> Nothing)
  DINT -> intArithValues DINT (\case VDInt x -> Just (fromIntegral x); _ -> Nothing)
  USINT -> intArithValues USINT (\case VUSInt x -> Just (fromIntegral x); _ -> Nothing)
  REAL -> realArith op $ \f -> Binary $ \a b -> case (a, b) of
    (VReal x, VReal y) -> f x y
    _ -> reference a b
  _ -> Binary reference
  where
    reference a b = fromOutcome (O.arith p op a b)
    intArithValues ty number =
      let mk = intToValue ty
          !ia = intArith p ty
          on o = Binary $ \a b -> case (number a, number b) of
            (Just x, Just y) -> intOp (\n f -> Flagged (mk n) f) (Plain . mk) Raised ia o x y
            _ -> reference a b
          {-# INLINE on #-}
       in eachArithOp on op
    {-# INLINE intArithValues #-}
    realArith o lift = eachArithOp (\o' -> lift (onReal o')) o
    onReal = O.realArithWith (\r o -> Flagged (VReal r) o) (Plain . VReal) Raised p
    {-# INLINE realArith #-}

-- | What the policies and the operand type decide for integer arithmetic,
-- worked out once (so that an operation does no case analysis on the
-- policies or the type, only on these fields).
data IntArith = IntArith
  { iaLo, iaHi :: {-# UNPACK #-} !Int -- ^ the type's range
  , iaWideLo, iaWideHi :: {-# UNPACK #-} !Int -- ^ the range of the intermediate result
  , iaOverflow :: !Overflow
  , iaPromoted :: !Bool -- ^ @arith-width = promote-32@: the result is narrowed to the type
  , iaNarrowSaturates :: !Bool
  , iaDivZero :: !DivZero
  , iaModZero :: !ModZero
  , iaModSign :: !ModSign
  }

intArith :: Policies -> BasicType -> IntArith
intArith p t =
  IntArith
    { iaLo = lo
    , iaHi = hi
    , iaWideLo = wl
    , iaWideHi = wh
    , iaOverflow = pOverflow p
    , iaPromoted = pArithWidth p == Promote32
    , iaNarrowSaturates = pNarrowInt p == NarrowSaturate
    , iaDivZero = pDivZero p
    , iaModZero = pModZero p
    , iaModSign = pModSign p
    }
  where
    (lo, hi) = range t
    (wl, wh) = case pArithWidth p of
      OperandType -> (lo, hi)
      Promote32 -> (dintLo, dintHi)

-- | "Stref.Operators" intArith on 'Int' (the same case analysis). The
-- outcome goes to one of three continuations: a number that sets
-- INTERNAL_OVERFLOW to the given state, a number that leaves it, a runtime
-- error (so that the interpreter's typed closures build no result at all).
-- Inlined where the operator is known, so that a closure holds the code of
-- one operator only.
intOp ::
  (Int -> Bool -> r) ->
  (Int -> r) ->
  (ErrorCode -> r) ->
  IntArith ->
  ArithOp ->
  Int ->
  Int ->
  r
intOp flagged plain raised ia op x y = case op of
  OpAdd -> setsFlag (x + y)
  OpSub -> setsFlag (x - y)
  OpMul -> setsFlag (x * y)
  OpDiv
    | y == 0 -> case iaDivZero ia of
        DivZeroError -> raised errDivisionByZero -- MT-OP-9, MT-ERR-2020
        DivZeroZero -> plain 0
        DivZeroTrap -> raised trapDivisionByZero
    | otherwise -> keepsFlag (O.divide (iaModSign ia) x y) -- MT-OP-10, A7
  OpMod
    | y == 0 -> case iaModZero ia of
        ModZeroZero -> plain 0 -- MT-OP-8
        ModZeroError -> raised errModZero
    | otherwise -> keepsFlag (O.modulo (iaModSign ia) x y)
  where
    wl = iaWideLo ia
    wh = iaWideHi ia
    -- MT-OP-7: + - * set the flag to whether the result overflowed
    setsFlag !exact
      | wl <= exact && exact <= wh = flagged (narrow exact) False
      | otherwise = case iaOverflow ia of
          Saturate -> flagged (narrow (max wl (min wh exact))) True -- MT-OP-6
          Wrap -> flagged (narrow (wrapIn wl wh exact)) True
          Trap -> raised trapOverflow
    {-# INLINE setsFlag #-}
    keepsFlag !exact
      | wl <= exact && exact <= wh = plain (narrow exact)
      | otherwise = case iaOverflow ia of
          Saturate -> plain (narrow (max wl (min wh exact)))
          Wrap -> plain (narrow (wrapIn wl wh exact))
          Trap -> raised trapOverflow
    {-# INLINE keepsFlag #-}
    -- under promote-32 the 32-bit result is narrowed to the type like an
    -- integer narrowing conversion (the identity under operand-type)
    narrow r
      | not (iaPromoted ia) = r
      | iaNarrowSaturates ia = max (iaLo ia) (min (iaHi ia) r)
      | otherwise = wrapIn (iaLo ia) (iaHi ia) r
    {-# INLINE narrow #-}
{-# INLINE intOp #-}

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
compareFast = eachCmpOp (\o -> Binary (go o (cmpWith o) (cmpWith o)))
  where
    go :: CmpOp -> (Int -> Int -> Bool) -> (Float -> Float -> Bool) -> Value -> Value -> Bool
    go op cmpI cmpR a b = case (a, b) of
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


-- | @f@ at the given operator, written out for each operator: every use of
-- @f@ receives its operator as a constant, so that a closure built by @f@
-- holds the code of that one operator (inlined where @f@ is known).
eachArithOp :: (ArithOp -> r) -> ArithOp -> r
eachArithOp f = \case
  OpAdd -> f OpAdd
  OpSub -> f OpSub
  OpMul -> f OpMul
  OpDiv -> f OpDiv
  OpMod -> f OpMod
{-# INLINE eachArithOp #-}

-- | 'eachArithOp' for the comparison operators.
eachCmpOp :: (CmpOp -> r) -> CmpOp -> r
eachCmpOp f = \case
  OpLt -> f OpLt
  OpGt -> f OpGt
  OpLe -> f OpLe
  OpGe -> f OpGe
  OpEq -> f OpEq
  OpNe -> f OpNe
{-# INLINE eachCmpOp #-}

-- | A comparison operator on numbers of one type (MT-OP-11; on 'Float' the
-- IEEE comparisons).
cmpWith :: Ord a => CmpOp -> a -> a -> Bool
cmpWith = \case
  OpLt -> (<)
  OpGt -> (>)
  OpLe -> (<=)
  OpGe -> (>=)
  OpEq -> (==)
  OpNe -> (/=)
{-# INLINE cmpWith #-}

-- | @f@ given the boxing of a number as a value of the type, written out for
-- each integer type: code built by @f@ boxes without looking at the type.
eachIntBox :: BasicType -> ((Int -> Value) -> r) -> r
eachIntBox t f = case t of
  INT -> f (\n -> VInt (fromIntegral n))
  DINT -> f (\n -> VDInt (fromIntegral n))
  USINT -> f (\n -> VUSInt (fromIntegral n))
  BYTE -> f (\n -> VByte (fromIntegral n))
  WORD -> f (\n -> VWord (fromIntegral n))
  DWORD -> f (\n -> VDWord (fromIntegral n))
  _ -> f (intToValue t)
{-# INLINE eachIntBox #-}

-- | The number of a value of an integer or bit-string type held by a cell's
-- pattern, given to @f@: the pattern's low bits as the type reads them
-- (@numberOf (wordToValue t w)@ without the 'Value'), the type chosen once.
eachPatternNumber :: BasicType -> ((Word32 -> Int) -> r) -> r
eachPatternNumber t f = case t of
  INT -> f (\w -> fromIntegral (fromIntegral w :: Int16))
  DINT -> f (\w -> fromIntegral (fromIntegral w :: Int32))
  USINT -> f (\w -> fromIntegral (fromIntegral w :: Word8))
  BYTE -> f (\w -> fromIntegral (fromIntegral w :: Word8))
  WORD -> f (\w -> fromIntegral (fromIntegral w :: Word16))
  _ -> f fromIntegral
{-# INLINE eachPatternNumber #-}

-- | Whether an arithmetic operation can end in a runtime error under the
-- policies: division and MOD (by zero, MT-OP-9, MT-OP-8), + - * on integers
-- only under the trapping overflow alternative; REAL + - * never (A6).
-- Operands of other types go to the reference, which rejects them.
arithCanFail :: Policies -> ArithOp -> BasicType -> Bool
arithCanFail p op t = case op of
  OpDiv -> True
  OpMod -> True
  _ -> case t of
    REAL -> False
    _
      | t `elem` [INT, DINT, USINT] -> case pOverflow p of
          Trap -> True
          _ -> False
      | otherwise -> True
