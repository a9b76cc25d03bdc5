{-# OPTIONS_GHC -O2 #-}
-- (the interpreter's hot path: bench/RESULTS.md measures -O2 against -O1)
-- | Run-time values with the exact width of their type (MT-TYPE-1). REAL is
-- IEEE binary32: a Haskell 'Float', whose arithmetic GHC performs in single
-- precision, so every operation rounds to binary32 (never via Double).
module Stref.Values
  ( Value (..)
  , valueType
  , defaultValue
  , valueToInteger
  , valueToInt
  , intToValue
  , integerToValue
  , realBits
  , realFromBits
  , showValue
  ) where

import Data.Int (Int16, Int32)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word16, Word32, Word8)
import GHC.Float (castFloatToWord32, castWord32ToFloat)
import Numeric (showHex)
import Stref.Types

data Value
  = VBool !Bool
  | VByte !Word8
  | VWord !Word16
  | VDWord !Word32
  | VUSInt !Word8
  | VInt !Int16
  | VDInt !Int32
  | VReal !Float
  deriving (Show)

-- | Values are equal when they have the same type and the same bits: REAL is
-- compared by its binary32 pattern, so @-0.0 /= 0.0@ and a NaN equals itself.
instance Eq Value where
  VReal a == VReal b = castFloatToWord32 a == castFloatToWord32 b
  VBool a == VBool b = a == b
  VByte a == VByte b = a == b
  VWord a == VWord b = a == b
  VDWord a == VDWord b = a == b
  VUSInt a == VUSInt b = a == b
  VInt a == VInt b = a == b
  VDInt a == VDInt b = a == b
  _ == _ = False

valueType :: Value -> BasicType
valueType = \case
  VBool _ -> BOOL
  VByte _ -> BYTE
  VWord _ -> WORD
  VDWord _ -> DWORD
  VUSInt _ -> USINT
  VInt _ -> INT
  VDInt _ -> DINT
  VReal _ -> REAL

-- | Table 4-7: FALSE, 0 or 0.0 (MT-VAR-3).
defaultValue :: BasicType -> Value
defaultValue = \case
  BOOL -> VBool False
  BYTE -> VByte 0
  WORD -> VWord 0
  DWORD -> VDWord 0
  USINT -> VUSInt 0
  INT -> VInt 0
  DINT -> VDInt 0
  REAL -> VReal 0

-- | The numeric value of an integer or bit-string value (bit strings read as
-- unsigned, MT-TYPE-2; BOOL as 0/1). 'Nothing' for REAL.
valueToInteger :: Value -> Maybe Integer
valueToInteger = \case
  VBool b -> Just (if b then 1 else 0)
  VByte w -> Just (fromIntegral w)
  VWord w -> Just (fromIntegral w)
  VDWord w -> Just (fromIntegral w)
  VUSInt w -> Just (fromIntegral w)
  VInt i -> Just (fromIntegral i)
  VDInt i -> Just (fromIntegral i)
  VReal _ -> Nothing

-- | The value of an integer or bit-string type whose bit pattern is the low
-- bits of the given integer (two's complement). For BOOL: non-zero is TRUE.
-- For REAL: the nearest binary32 of the integer.
integerToValue :: BasicType -> Integer -> Value
integerToValue t n = case t of
  BOOL -> VBool (n /= 0)
  BYTE -> VByte (fromInteger n)
  WORD -> VWord (fromInteger n)
  DWORD -> VDWord (fromInteger n)
  USINT -> VUSInt (fromInteger n)
  INT -> VInt (fromInteger n)
  DINT -> VDInt (fromInteger n)
  REAL -> VReal (fromInteger n)

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

realBits :: Float -> Word32
realBits = castFloatToWord32

realFromBits :: Word32 -> Float
realFromBits = castWord32ToFloat

-- | ST-like rendering: TRUE/FALSE, decimal integers, bit strings in hex,
-- REAL with the shortest decimal that reads back as the same binary32.
showValue :: Value -> Text
showValue = \case
  VBool b -> if b then "TRUE" else "FALSE"
  VByte w -> hexLit 2 (fromIntegral w)
  VWord w -> hexLit 4 (fromIntegral w)
  VDWord w -> hexLit 8 (fromIntegral w)
  VUSInt w -> T.pack (show w)
  VInt i -> T.pack (show i)
  VDInt i -> T.pack (show i)
  VReal r -> T.pack (show r)
  where
    hexLit :: Int -> Integer -> Text
    hexLit width n =
      let h = showHex n ""
       in T.pack ("16#" ++ replicate (width - length h) '0' ++ map toUpperHex h)
    toUpperHex c = if c >= 'a' && c <= 'f' then toEnum (fromEnum c - 32) else c
