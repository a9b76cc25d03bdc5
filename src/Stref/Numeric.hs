-- | Exact numeric helpers shared by the operators, the conversions and the
-- checker: correctly rounded binary32, two's complement wrapping, clamping,
-- and the admissible ranges of integer literals (Table 4-15).
module Stref.Numeric
  ( realLiteral
  , roundToReal
  , realMax
  , realInfinity
  , isRealInfinite
  , isRealNaN
  , realToRational
  , wrapTo
  , clampTo
  , fitsIn
  , integerLiteralFits
  ) where

import Data.Bits (shiftL, shiftR)
import Data.Ratio (denominator, numerator)
import Stref.Types
import Stref.Values (realFromBits)

-- | The binary32 value of a decimal literal: the exact rational rounded once
-- to the nearest binary32, ties to the even significand (IEEE 754
-- roundTiesToEven, MT-TYPE-1 Note 2). Magnitudes from @2^128 - 2^103@ up
-- round to infinity, as IEEE prescribes; the checker decides whether such a
-- literal is admissible.
realLiteral :: Rational -> Float
realLiteral = roundToReal

-- | Round an exact rational to the nearest binary32, ties to even. A negative
-- value too small to represent becomes @-0.0@.
roundToReal :: Rational -> Float
roundToReal r
  | r == 0 = realFromBits 0
  | r < 0 = negate (roundPositive (negate r))
  | otherwise = roundPositive r

-- | Rounding of a positive rational, by integer arithmetic only. With @sh@
-- the weight of the last significand bit (@2^sh@) and @m@ the significand
-- rounded to an integer, the binary32 bit pattern is @(sh + 149) * 2^23 + m@
-- for normal and subnormal numbers alike; a carry out of the significand
-- moves into the exponent field by itself, and a pattern at or above the one
-- of infinity means overflow.
roundPositive :: Rational -> Float
roundPositive r
  | pattern >= infinityBits = realInfinity
  | otherwise = realFromBits (fromInteger pattern)
  where
    n = numerator r
    d = denominator r
    e0 = floorLog2 n - floorLog2 d
    -- 2^e <= r < 2^(e+1)
    e = if r >= 2 ^^ e0 then e0 else e0 - 1
    sh = max e (-126) - 23
    (num, den)
      | sh >= 0 = (n, d `shiftL` sh)
      | otherwise = (n `shiftL` negate sh, d)
    (q, rm) = num `quotRem` den
    m = case compare (2 * rm) den of
      LT -> q
      GT -> q + 1
      EQ -> if even q then q else q + 1
    pattern = toInteger (sh + 149) * 2 ^ (23 :: Int) + m
    infinityBits = 0x7F800000

-- | Position of the highest set bit of a positive integer.
floorLog2 :: Integer -> Int
floorLog2 = go (-1)
  where
    go !acc y
      | y >= 2 ^ (64 :: Int) = go (acc + 64) (y `shiftR` 64)
      | y == 0 = acc
      | otherwise = go (acc + 1) (y `shiftR` 1)

-- | The largest finite binary32, 3.4028235e38 = (2^24 - 1) * 2^104 (A6).
realMax :: Float
realMax = 3.4028235e38 -- realFromBits 0x7F7FFFFF (NumericSpec checks the bits)

realInfinity :: Float
realInfinity = realFromBits 0x7F800000

-- | By comparison, not by the bit pattern: the same answer (only the
-- infinities lie beyond the largest finite binary32, and NaN compares false),
-- without moving the value out of a floating-point register.
isRealInfinite :: Float -> Bool
isRealInfinite x = x > realMax || x < negate realMax
{-# INLINE isRealInfinite #-}

-- | NaN is the only value unequal to itself.
isRealNaN :: Float -> Bool
isRealNaN x = x /= x
{-# INLINE isRealNaN #-}

-- | The exact value of a finite binary32 ('Nothing' for infinities and NaN).
realToRational :: Float -> Maybe Rational
realToRational x
  | isRealNaN x || isRealInfinite x = Nothing
  | otherwise = Just (toRational x)

-- | The integer of the type's range congruent to the argument modulo 2^bits:
-- two's complement wrapping for INT and DINT, reduction modulo 2^n for the
-- unsigned types. BOOL and REAL have no integer range and are left alone.
wrapTo :: BasicType -> Integer -> Integer
wrapTo t x = case intRange t of
  Just (lo, hi) -> lo + (x - lo) `mod` (hi - lo + 1)
  Nothing -> x

-- | The nearest integer of the type's range.
clampTo :: BasicType -> Integer -> Integer
clampTo t x = case intRange t of
  Just (lo, hi) -> max lo (min hi x)
  Nothing -> x

fitsIn :: BasicType -> Integer -> Bool
fitsIn t x = case intRange t of
  Just (lo, hi) -> lo <= x && x <= hi
  Nothing -> False

-- | May an integer literal with this value stand where the type is expected?
-- MT-CONST-2 (Table 4-15, with the DWORD maximum corrected to 4294967295):
-- USINT and BYTE 0..255, INT -32768..32767, WORD 0..65535, DINT the 32-bit
-- signed range, DWORD 0..4294967295; BOOL only 0 and 1 (MT-LEX-16); REAL
-- the INT range, read as INT then converted (MT-CONST-4, decision A10).
integerLiteralFits :: BasicType -> Integer -> Bool
integerLiteralFits t n = case t of
  BOOL -> n == 0 || n == 1
  REAL -> fitsIn INT n
  _ -> fitsIn t n
