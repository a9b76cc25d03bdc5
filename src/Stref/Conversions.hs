-- | Type conversions (catalogue §3, Table 4-6). The static part (which
-- functions exist, which conversions are implicit) serves the checker; the
-- run-time meaning of each row is 'convert'.
module Stref.Conversions
  ( ConversionRow (..)
  , conversionTable
  , conversionRow
  , conversionName
  , ConversionFunction (..)
  , lookupConversionFunction
  , implicitConversion
  , convert
  ) where

import Data.Char (toUpper)
import Data.List (find)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Policy
import Stref.Types
import Stref.Values

-- | One row of Table 4-6: its number (C01..C53), source and target, and
-- whether MasterTool inserts it implicitly (MT-CONV-6).
data ConversionRow = ConversionRow
  { crNumber :: Int
  , crFrom :: BasicType
  , crTo :: BasicType
  , crImplicit :: Bool
  }
  deriving (Eq, Show)

-- | MT-CONV-5: the 53 functions, in the manual's order. REAL_TO_BYTE,
-- REAL_TO_USINT and REAL_TO_DWORD do not exist (MT-CONV-7, decision A8).
conversionTable :: [ConversionRow]
conversionTable = zipWith row [1 ..] pairs
  where
    row n (f, t) = ConversionRow n f t ((f, t) `elem` mastertoolImplicit)
    pairs =
      [(BOOL, t) | t <- [BYTE, WORD, DWORD, USINT, INT, DINT, REAL]]
        ++ [(BYTE, t) | t <- [BOOL, USINT, WORD, DWORD, INT, DINT, REAL]]
        ++ [(WORD, t) | t <- [BOOL, BYTE, USINT, INT, DWORD, DINT, REAL]]
        ++ [(DWORD, t) | t <- [BOOL, BYTE, USINT, WORD, INT, DINT, REAL]]
        ++ [(USINT, t) | t <- [BOOL, BYTE, WORD, DWORD, INT, DINT, REAL]]
        ++ [(INT, t) | t <- [BOOL, BYTE, USINT, WORD, DWORD, DINT, REAL]]
        ++ [(DINT, t) | t <- [BOOL, BYTE, USINT, WORD, INT, DWORD, REAL]]
        ++ [(REAL, t) | t <- [BOOL, WORD, INT, DINT]]

-- | MT-CONV-6: the seven implicit edges, not transitively closed (A9).
mastertoolImplicit :: [(BasicType, BasicType)]
mastertoolImplicit =
  [(BYTE, WORD), (BYTE, DWORD), (WORD, DWORD), (USINT, INT), (USINT, DINT), (INT, DINT), (INT, REAL)]

conversionRow :: BasicType -> BasicType -> Maybe ConversionRow
conversionRow f t = find (\r -> crFrom r == f && crTo r == t) conversionTable

conversionName :: BasicType -> BasicType -> Text
conversionName f t = typeName f <> "_TO_" <> typeName t

-- | A conversion function named in the source (MT-CONV-2, MT-CONV-8).
data ConversionFunction
  = Explicit BasicType BasicType -- ^ @<S>_TO_<T>@, a row of Table 4-6
  | AnyTo BasicType -- ^ @ANY_TO_<T>@
  deriving (Eq, Show)

-- | Recognise a conversion function's name (case-insensitive, MT-LEX-5).
-- @REAL_TO_BYTE@ and the other pairs missing from Table 4-6 are not
-- functions (decision A8); neither is @T_TO_T@.
lookupConversionFunction :: Text -> Maybe ConversionFunction
lookupConversionFunction name = case T.splitOn "_TO_" (T.map toUpper name) of
  ["ANY", t] -> AnyTo <$> parseTypeName t
  [f, t] -> do
    f' <- parseTypeName f
    t' <- parseTypeName t
    Explicit f' t' <$ conversionRow f' t'
  _ -> Nothing

-- | Does the checker insert the conversion from the first type to the second
-- on its own? (the @implicit-conversions@ policy)
implicitConversion :: ImplicitConversions -> BasicType -> BasicType -> Bool
implicitConversion policy f t = case policy of
  ImplicitMastertool -> (f, t) `elem` mastertoolImplicit
  -- IEC widening: the same edges, closed under composition (adds USINT->REAL).
  ImplicitIecWidening -> (f, t) `elem` (mastertoolImplicit ++ [(USINT, REAL)])
  -- CODESYS: every value-preserving widening, across the integer and
  -- bit-string families too; never a narrowing.
  ImplicitCodesys ->
    (f, t)
      `elem` ( mastertoolImplicit
                 ++ [(USINT, REAL), (BYTE, INT), (BYTE, DINT), (BYTE, REAL), (WORD, DINT), (WORD, REAL), (USINT, WORD), (USINT, DWORD), (BYTE, USINT), (USINT, BYTE)]
             )

-- | The run-time meaning of a conversion (Table 4-6 rows C01-C53; identity
-- when the types agree). STUB: owned by the numeric work.
convert :: Policies -> BasicType -> BasicType -> Value -> Value
convert _ f t v
  | f == t = v
  | otherwise = defaultValue t
