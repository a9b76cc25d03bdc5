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
  , convertAny
  ) where

import Data.Char (toUpper)
import Data.List (find)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Numeric
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
  ImplicitNone -> False

-- | The run-time meaning of a conversion (Table 4-6 rows C01-C53; identity
-- when the types agree), under the @real-to-int@ and @narrow-int@ policies.
-- Conversions never touch INTERNAL_OVERFLOW (MT-CONV-14). The source is the
-- value's own type; the first argument only documents the call site.
--
-- The pairs missing from the table (REAL to BYTE, USINT, DWORD) get the
-- ANY_TO semantics of decision A8 / MT-CONV-7: through DINT, like C51.
convert :: Policies -> BasicType -> BasicType -> Value -> Value
convert p _ target v = convertAny p target v

-- | @ANY_TO_<target>@ (MT-CONV-8): the row of Table 4-6 for the argument's
-- type, the identity for the same type, and for REAL to BYTE, USINT or DWORD
-- the conversion to DINT followed by DINT to the target (A8, MT-CONV-7).
convertAny :: Policies -> BasicType -> Value -> Value
convertAny p target v
  | valueType v == target = v
  | otherwise = case v of
      VBool b -> integerToValue target (if b then 1 else 0) -- C01-C07
      VReal r -> fromReal r
      _ -> maybe v fromInteger' (valueToInteger v)
  where
    -- C08, C15, C22, C29, C36, C43: zero is FALSE, anything else TRUE.
    fromInteger' n = case target of
      BOOL -> VBool (n /= 0)
      REAL -> VReal (roundToReal (fromInteger n)) -- C14, C21, C28, C35, C42, C49
      _
        -- C16, C17, C23-C26, C37, C38, C44-C47: a narrower target keeps the
        -- low bits, or saturates under narrow-int=saturate.
        | typeBits target < typeBits (valueType v) -> integerToValue target (narrow n)
        -- Same width (C09, C18, C27, C30, C39, C48): the same bits. Wider
        -- (C10-C13, C19, C20, C31-C34, C40, C41): the value, sign-extended
        -- for INT and DINT (C40), i.e. again the low bits of the value.
        | otherwise -> integerToValue target n
    narrow n = case pNarrowInt p of
      NarrowWrap -> wrapTo target n
      NarrowSaturate -> clampTo target n
    fromReal r = case target of
      BOOL -> VBool (r /= 0) -- C50: -0.0 is FALSE, NaN is TRUE (not zero)
      INT -> VInt (fromInteger (realToInteger (pRealToInt p) INT r)) -- C52
      DINT -> VDInt (fromInteger (realToInteger (pRealToInt p) DINT r)) -- C53
      -- C51 (WORD), and A8 for BYTE, USINT, DWORD: through DINT.
      _ -> convertAny p target (VDInt (fromInteger (realToInteger (pRealToInt p) DINT r)))

-- | REAL to INT or DINT (MT-CONV-9, C52, C53), per @real-to-int@: the
-- integer part (truncation toward zero) or the nearest integer with ties to
-- even, then clamped to the type's range or wrapped modulo 2^n. NaN gives 0.
-- Infinities give the limit of their sign when saturating, and 0 when
-- wrapping (every binary32 from 2^55 up is a multiple of 2^32, so that is
-- the limit of the wrapped values).
realToInteger :: RealToInt -> BasicType -> Float -> Integer
realToInteger policy t r = case realToRational r of
  Nothing
    | isRealNaN r -> 0
    | otherwise -> case policy of
        RoundEvenWrap -> 0
        _ -> clampTo t (if r > 0 then hugeInteger else negate hugeInteger)
  Just q -> case policy of
    TruncateSaturate -> clampTo t (truncate q)
    RoundEvenSaturate -> clampTo t (round q)
    RoundEvenWrap -> wrapTo t (round q)
  where
    hugeInteger = 2 ^ (200 :: Int)
