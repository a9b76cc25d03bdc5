-- | Data types (catalogue §2): the eight basic types, their groups, arrays.
module Stref.Types
  ( BasicType (..)
  , Type (..)
  , allBasicTypes
  , typeName
  , parseTypeName
  , isAnyInt
  , isAnyNum
  , isAnyBit
  , isBitString
  , typeBits
  , typeBytes
  , elementType
  , intRange
  ) where

import Data.Text (Text)
import qualified Data.Text as T

-- | MT-TYPE-1: the eight basic types of MasterTool XE.
data BasicType = BOOL | BYTE | WORD | DWORD | USINT | INT | DINT | REAL
  deriving (Eq, Ord, Show, Read, Enum, Bounded)

-- | A variable's type: basic, or a one-dimensional array (MT-TYPE-4).
data Type
  = Basic BasicType
  | Array Integer Integer BasicType -- ^ lower bound, upper bound, element
  deriving (Eq, Ord, Show)

allBasicTypes :: [BasicType]
allBasicTypes = [minBound .. maxBound]

typeName :: BasicType -> Text
typeName = T.pack . show

-- | Case-insensitive (MT-LEX-5).
parseTypeName :: Text -> Maybe BasicType
parseTypeName t = lookup (T.toUpper t) [(typeName b, b) | b <- allBasicTypes]

-- | MT-TYPE-5: ANY_INT = {USINT, INT, DINT}.
isAnyInt :: BasicType -> Bool
isAnyInt t = t `elem` [USINT, INT, DINT]

-- | MT-TYPE-5: ANY_NUM = ANY_INT + REAL.
isAnyNum :: BasicType -> Bool
isAnyNum t = isAnyInt t || t == REAL

-- | MT-TYPE-5: ANY_BIT = {BOOL, BYTE, WORD, DWORD}.
isAnyBit :: BasicType -> Bool
isAnyBit t = t `elem` [BOOL, BYTE, WORD, DWORD]

-- | MT-TYPE-2: BYTE, WORD, DWORD are bit strings without a numeric range.
isBitString :: BasicType -> Bool
isBitString t = t `elem` [BYTE, WORD, DWORD]

-- | Width in bits (Table 2-1).
typeBits :: BasicType -> Int
typeBits = \case
  BOOL -> 1
  BYTE -> 8
  USINT -> 8
  WORD -> 16
  INT -> 16
  DWORD -> 32
  DINT -> 32
  REAL -> 32

-- | Storage size in bytes (Table 4-5; MT-LIM-10 for the 3 KB data area).
typeBytes :: Type -> Integer
typeBytes = \case
  Basic t -> basicBytes t
  Array lo hi t -> (hi - lo + 1) * basicBytes t
  where
    basicBytes t = if t == BOOL then 1 else fromIntegral (typeBits t `div` 8)

elementType :: Type -> BasicType
elementType (Basic t) = t
elementType (Array _ _ t) = t

-- | The numeric range of an integer type; bit strings read as unsigned
-- (MT-TYPE-1, MT-TYPE-2). 'Nothing' for BOOL and REAL.
intRange :: BasicType -> Maybe (Integer, Integer)
intRange = \case
  USINT -> Just (0, 255)
  INT -> Just (-32768, 32767)
  DINT -> Just (-2147483648, 2147483647)
  BYTE -> Just (0, 255)
  WORD -> Just (0, 65535)
  DWORD -> Just (0, 4294967295)
  BOOL -> Nothing
  REAL -> Nothing
