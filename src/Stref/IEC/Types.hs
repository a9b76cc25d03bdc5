-- | The data types of IEC 61131-3 (ed.2 §2.3; Tecomat §3.2): the elementary
-- types with their exact widths, the generic families of the standard
-- functions, and the derived types (aliases resolved away, enumerations,
-- subranges, arrays, structures) and function-block types.
module Stref.IEC.Types
  ( Elem (..)
  , Type (..)
  , allElems
  , elemName
  , parseElemName
  , isInt
  , isSignedInt
  , isBitString
  , isAnyBit
  , isAnyInt
  , isAnyReal
  , isAnyNum
  , isAnyDate
  , isTimeLike
  , intBits
  , intRange
  , typeText
  , baseElem
  , sameType
  , upperName
  , asciiUpper
  ) where

import Data.Char (chr, isAscii, ord)
import Data.Text (Text)
import GHC.Arr (Array, listArray, (!))
import qualified Data.Text as T

-- | The elementary types (TC-TYPE-1..17; LINT, ULINT, LWORD and LTIME are
-- for the dialects that have them: TC-TYPE-18).
data Elem
  = BOOL
  | SINT
  | INT
  | DINT
  | LINT
  | USINT
  | UINT
  | UDINT
  | ULINT
  | BYTE
  | WORD
  | DWORD
  | LWORD
  | REAL
  | LREAL
  | TIME
  | LTIME
  | DATE
  | TOD
  | DT
  deriving (Eq, Ord, Show, Read, Enum, Bounded)

-- | A type after the checker resolved names and aliases.
data Type
  = TElem Elem
  | TString Bool Int -- ^ wide?, capacity in characters
  | TArray [(Integer, Integer)] Type -- ^ bounds of each dimension (TC-TYPE-38..41)
  | TStruct Text [(Text, Type)] -- ^ the type's name ("" when anonymous) and its fields in order
  | TEnum Text [Text] -- ^ the type's name and its values in order (TC-TYPE-21)
  | TSubrange Elem Integer Integer -- ^ base type and bounds (TC-TYPE-32)
  | TFB Text -- ^ an instance of the named function block (standard or user)
  | TProgram Text -- ^ a program instance
  | TNumEnum Text Elem [(Text, Integer)]
  -- ^ policy enumerations = integer (CODESYS, NX-TYPE-57..67): the type's
  -- name, its base type and its values; a value is a number of the base type
  | TPointer Type -- ^ CODESYS: @POINTER TO T@; its value is an address, a DWORD (NX-TYPE-74, NX-TYPE-78)
  | TUnion Text [(Text, Type)] -- ^ CODESYS: a @UNION@, whose members share their storage (NX-TYPE-72, NX-TYPE-73)
  | TNamed Text
  -- ^ only under 'TPointer': a structure or union named by its TYPE, looked
  -- up when the pointer is followed, so that a structure may point at its
  -- own type (a list's node)
  deriving (Eq, Ord, Show)

allElems :: [Elem]
allElems = [minBound .. maxBound]

elemName :: Elem -> Text
elemName = T.pack . show

-- | Case-insensitive, with the long spellings TIME_OF_DAY and DATE_AND_TIME.
parseElemName :: Text -> Maybe Elem
parseElemName t = case T.toUpper t of
  "TIME_OF_DAY" -> Just TOD
  "DATE_AND_TIME" -> Just DT
  u -> lookup u [(elemName e, e) | e <- allElems]

-- | The integers and bit strings (not BOOL).
isInt :: Elem -> Bool
isInt e = isAnyInt e || isBitString e

isSignedInt :: Elem -> Bool
isSignedInt e = e `elem` [SINT, INT, DINT, LINT]

isBitString :: Elem -> Bool
isBitString e = e `elem` [BYTE, WORD, DWORD, LWORD]

-- | ANY_BIT (Tab.3.7): BOOL and the bit strings.
isAnyBit :: Elem -> Bool
isAnyBit e = e == BOOL || isBitString e

-- | ANY_INT (Tab.3.7).
isAnyInt :: Elem -> Bool
isAnyInt e = e `elem` [SINT, INT, DINT, LINT, USINT, UINT, UDINT, ULINT]

isAnyReal :: Elem -> Bool
isAnyReal e = e == REAL || e == LREAL

isAnyNum :: Elem -> Bool
isAnyNum e = isAnyInt e || isAnyReal e

-- | ANY_DATE (Tab.3.7): DATE, TOD, DT.
isAnyDate :: Elem -> Bool
isAnyDate e = e `elem` [DATE, TOD, DT]

isTimeLike :: Elem -> Bool
isTimeLike e = e `elem` [TIME, LTIME, DATE, TOD, DT]

-- | Width of an integer or bit-string type (Tab.3.6).
intBits :: Elem -> Int
intBits = \case
  SINT -> 8
  USINT -> 8
  BYTE -> 8
  INT -> 16
  UINT -> 16
  WORD -> 16
  DINT -> 32
  UDINT -> 32
  DWORD -> 32
  LINT -> 64
  ULINT -> 64
  LWORD -> 64
  BOOL -> 1
  TIME -> 32 -- TC-TYPE-19: a signed 32-bit count of milliseconds
  LTIME -> 64
  _ -> 64

-- | The range of an integer or bit-string type (Tab.3.6): 'rangeOf',
-- computed once for each type.
intRange :: Elem -> (Integer, Integer)
intRange e = ranges ! fromEnum e

ranges :: Array Int (Integer, Integer)
ranges = listArray (fromEnum (minBound :: Elem), fromEnum (maxBound :: Elem)) [rangeOf e | e <- [minBound .. maxBound]]

rangeOf :: Elem -> (Integer, Integer)
rangeOf e
  | isSignedInt e || e == TIME || e == LTIME = (negate (2 ^ (n - 1)), 2 ^ (n - 1) - 1)
  | otherwise = (0, 2 ^ n - 1)
  where
    n = intBits e

typeText :: Type -> Text
typeText = \case
  TElem e -> elemName e
  TString w n -> (if w then "WSTRING[" else "STRING[") <> T.pack (show n) <> "]"
  TArray bs t -> "ARRAY [" <> T.intercalate ", " [T.pack (show a) <> ".." <> T.pack (show b) | (a, b) <- bs] <> "] OF " <> typeText t
  TStruct n _ -> if T.null n then "STRUCT" else n
  TUnion n _ -> if T.null n then "UNION" else n
  TEnum n _ -> if T.null n then "an enumeration" else n
  TSubrange e a b -> elemName e <> " (" <> T.pack (show a) <> ".." <> T.pack (show b) <> ")"
  TFB n -> n
  TProgram n -> n
  TPointer t -> "POINTER TO " <> typeText t
  TNamed n -> n
  TNumEnum n _ _ -> n

-- | The elementary type under a subrange, or of an elementary type.
baseElem :: Type -> Maybe Elem
baseElem = \case
  TElem e -> Just e
  TSubrange e _ _ -> Just e
  TNumEnum _ e _ -> Just e
  _ -> Nothing

-- | Types that hold the same values: strings of any capacity are one type
-- for assignment (truncation is a policy, not a type error).
sameType :: Type -> Type -> Bool
sameType a b = case (a, b) of
  (TString w1 _, TString w2 _) -> w1 == w2
  (TSubrange e _ _, t) -> sameType (TElem e) t
  (t, TSubrange e _ _) -> sameType t (TElem e)
  -- NX-TYPE-60, NX-TYPE-61: CODESYS's enumerated values are numbers
  (TNumEnum _ e _, t) -> sameType (TElem e) t
  (t, TNumEnum _ e _) -> sameType t (TElem e)
  -- arrays are one type when their bounds are equal, not only their lengths:
  -- no implicit conversion (TC-CONV-3, open; docs/tecomat.md), so
  -- ARRAY[0..2] and ARRAY[1..3] are not assigned to each other
  (TArray b1 t1, TArray b2 t2) -> b1 == b2 && sameType t1 t2
  _ -> a == b

-- | A name in upper case: names compare without case (TC-LEX-15). An ASCII
-- name (nearly every one) is mapped without Unicode's case tables.
upperName :: Text -> Text
upperName t
  | T.all isAscii t = T.map asciiUpper t
  | otherwise = T.toUpper t

-- | An ASCII letter in upper case; every other character as it is.
asciiUpper :: Char -> Char
asciiUpper c = if c >= 'a' && c <= 'z' then chr (ord c - 32) else c
