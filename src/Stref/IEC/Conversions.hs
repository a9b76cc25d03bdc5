-- | The type conversion functions (Tecomat catalogue §3, Tab.3.12; IEC
-- 61131-3 ed.2 §2.5.1.5.1): @X_TO_Y@ between the elementary types and
-- STRING (TC-CONV-6, TC-CONV-10..18), TRUNC (TC-CONV-7) and the BCD
-- conversions (TC-CONV-8, TC-CONV-9). Which names exist, their typing, and
-- their meaning under the policies @narrow-int@ and @real-to-int@.
--
-- Under @standard-library = codesys@ the conversions are CODESYS's (Nexto
-- catalogue §3.2): the time types are the numbers the controller stores
-- (TIME and TOD milliseconds, LTIME nanoseconds, DATE and DT seconds since
-- 1970, NX-CONV-26, NX-CONV-29), so they convert to and from BOOL and every
-- number; STRING converts to them from their literals (NX-CONV-33);
-- TRUNC_INT (NX-CONV-36), ANY_TO_Y and ANY_NUM_TO_Y (NX-CONV-38) exist; the
-- BCD conversions are util.library's two functions ("Stref.IEC.Standard").
--
-- 'convert' is the meaning of one conversion between two types; the
-- checker also uses it for the conversions it inserts itself.
module Stref.IEC.Conversions
  ( -- * Names
    conversionName
  , ConvType (..)
  , Conversion (..)
  , conversionFunction
  , isConversionName
  , truncName
  , codesysConversions
    -- * Typing
  , conversionType
    -- * Meaning
  , conversion
  , convert
  , trunc
  , truncTo
  , bcdToInt
  , intToBcd
  , narrowInt
  , realToInteger
    -- * Text of values and values of text
  , valueText
  , realText
  , parseIntegerText
  , parseRealText
  , RealText (..)
  ) where

import Control.Applicative ((<|>))
import Control.Monad (guard)
import Data.Char (digitToInt, isDigit, isHexDigit)
import Data.Maybe (fromMaybe)
import Data.Text (Text)
import qualified Data.Text as T
import GHC.Float (double2Float, float2Double)
import Numeric (floatToDigits)
import Stref.IEC.Operators (finite, fitsUnder, illTyped, rangeUnder, realOverflowFrom, wrapUnder)
import Stref.IEC.Parser (timeLiteral)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

------------------------------------------------------------------------
-- Names

-- | One side of an @X_TO_Y@ name: an elementary type or STRING.
data ConvType = CElem Elem | CString
  deriving (Eq, Show)

-- | A conversion function named in a program.
data Conversion
  = Convert ConvType ConvType -- ^ @X_TO_Y@ (TC-CONV-6)
  | Trunc -- ^ @TRUNC@: ANY_REAL to DINT (TC-CONV-7)
  | TruncInt -- ^ CODESYS: @TRUNC_INT@, ANY_REAL to INT (NX-CONV-36)
  | AnyTo Bool ConvType -- ^ CODESYS: @ANY_TO_Y@ (False) or @ANY_NUM_TO_Y@ (True) (NX-CONV-38)
  | BcdToInt (Maybe Elem) Elem -- ^ @BCD_TO_Y@ (any bit string) or @X_BCD_TO_Y@ (TC-CONV-8)
  | IntToBcd Elem (Maybe Elem) -- ^ @X_TO_BCD@ (the bit string of X's width) or @X_TO_BCD_Y@ (TC-CONV-9)
  deriving (Eq, Show)

-- | TC-CONV-7: the name of the truncation.
truncName :: Text
truncName = "TRUNC"

-- | Are the conversions CODESYS's (policy @standard-library@)?
codesysConversions :: Policies -> Bool
codesysConversions p = pStandardLibrary p == LibraryCodesys

-- | An @X_TO_Y@ name between two elementary types, case-insensitive, with
-- the long spellings TIME_OF_DAY and DATE_AND_TIME
-- (@DATE_AND_TIME_TO_TIME_OF_DAY@ = @DT_TO_TOD@, TC-CONV-10, TC-CONV-11).
-- 'Nothing' for every other name, also for the conversions that involve
-- STRING, TRUNC or BCD ('conversionFunction' knows those).
conversionName :: Policies -> Text -> Maybe (Elem, Elem)
conversionName p n = case conversionFunction p n of
  Just (Convert (CElem x) (CElem y)) -> Just (x, y)
  _ -> Nothing

-- | Any conversion function: @X_TO_Y@ for the pairs of 'convertible',
-- @TRUNC@, @BCD_TO_Y@, @X_BCD_TO_Y@, @X_TO_BCD@, @X_TO_BCD_Y@; under
-- @standard-library = codesys@ also @TRUNC_INT@, @ANY_TO_Y@ and
-- @ANY_NUM_TO_Y@, and none of the BCD forms (util.library's BCD_TO_INT and
-- INT_TO_BCD are functions of their own, NX-FB-34).
conversionFunction :: Policies -> Text -> Maybe Conversion
conversionFunction p name
  | n == truncName = Just Trunc
  | codesys && n == "TRUNC_INT" = Just TruncInt -- NX-CONV-36
  | codesys, Just y <- T.stripPrefix "ANY_NUM_TO_" n = AnyTo True <$> (side y >>= \t -> t <$ guard (numberSide t)) -- NX-CONV-38
  | codesys, Just y <- T.stripPrefix "ANY_TO_" n = AnyTo False <$> side y -- NX-CONV-38
  | otherwise = case T.splitOn "_TO_" n of
      [a, b]
        | codesys -> plain a b
        | otherwise -> plain a b <|> fromBcd a b <|> toBcd a b
      _ -> Nothing
  where
    n = upperName name
    codesys = codesysConversions p
    plain a b = do
      x <- side a
      y <- side b
      guard (convertible p x y)
      Just (Convert x y)
    side s = if s == "STRING" then Just CString else CElem <$> parseElemName s
    numberSide = \case
      CElem e -> isAnyNum e
      CString -> False
    intNamed s = parseElemName s >>= \e -> e <$ guard (isAnyInt e)
    bitNamed s = parseElemName s >>= \e -> e <$ guard (isBitString e)
    fromBcd a b = do
      y <- intNamed b
      if a == "BCD"
        then Just (BcdToInt Nothing y)
        else do
          x <- T.stripSuffix "_BCD" a >>= bitNamed
          Just (BcdToInt (Just x) y)
    toBcd a b = do
      x <- intNamed a
      if b == "BCD"
        then Just (IntToBcd x Nothing)
        else do
          y <- T.stripPrefix "BCD_" b >>= bitNamed
          Just (IntToBcd x (Just y))

isConversionName :: Policies -> Text -> Bool
isConversionName p = maybe False (const True) . conversionFunction p

-- | TC-CONV-18 (open: "ANY to ANY", no list). Decision: the pairs that have
-- a meaning without an invented encoding:
--
-- * among BOOL, the integers, the bit strings and the reals: every pair
--   (TC-CONV-6, TC-CONV-12..14);
-- * TIME and LTIME with each other and with the integers, bit strings and
--   reals (TC-CONV-16): TIME counts milliseconds, LTIME nanoseconds;
-- * DT_TO_TOD and DT_TO_DATE (TC-CONV-10, TC-CONV-11);
-- * every elementary type to STRING, and STRING to BOOL, the integers, the
--   bit strings and the reals (TC-CONV-17).
--
-- Not: a type to itself, DATE/TOD/DT to or from numbers (no epoch or unit is
-- documented), BOOL with durations, STRING to the time types, WSTRING.
--
-- Under @standard-library = codesys@ ("any elementary type converts into
-- any other", NX-CONV-1) also: BOOL with TIME, LTIME, TOD, DATE and DT
-- (NX-CONV-12..16); TOD, DATE and DT with the integers, bit strings and
-- reals (NX-CONV-26, NX-CONV-29); STRING to TIME, LTIME, TOD, DATE and DT
-- (NX-CONV-33). Not: the time types among themselves beyond TIME/LTIME and
-- DT_TO_TOD/DT_TO_DATE (the manual shows none).
convertible :: Policies -> ConvType -> ConvType -> Bool
convertible p a b = case (a, b) of
  (CElem x, CElem y) -> x /= y && (elemPair x y || codesys && codesysPair x y)
  (CElem _, CString) -> True
  (CString, CElem y) -> numeric y || codesys && isTimeLike y
  (CString, CString) -> False
  where
    codesys = codesysConversions p
    numeric e = e == BOOL || isInt e || isAnyReal e
    number e = isInt e || isAnyReal e
    elemPair x y
      | numeric x && numeric y = True
      | isDuration x = isDuration y || number y
      | isDuration y = number x
      | otherwise = (x, y) `elem` [(DT, TOD), (DT, DATE)]
    codesysPair x y =
      (x == BOOL && isTimeLike y) || (isTimeLike x && y == BOOL)
        || (isAnyDate x && number y) || (number x && isAnyDate y)

isDuration :: Elem -> Bool
isDuration e = e == TIME || e == LTIME

------------------------------------------------------------------------
-- Typing

-- | The result type of a conversion function applied to arguments of these
-- types ('Nothing': not a conversion function). The argument must have the
-- type named first (a subrange of it will do); X_TO_STRING gives a STRING
-- of the default capacity (@string-length@); TRUNC gives DINT; BCD_TO_Y
-- takes any bit string; X_TO_BCD gives the bit string of X's width.
-- TRUNC_INT takes REAL or LREAL and gives INT; ANY_TO_Y takes every type
-- that converts to Y (and Y itself), ANY_NUM_TO_Y every ANY_NUM.
conversionType :: Policies -> Text -> [Type] -> Maybe (Either Text Type)
conversionType p name ts = check <$> conversionFunction p name
  where
    check c = case ts of
      [t] -> argument c t
      _ -> Left (name <> " takes one argument, not " <> T.pack (show (length ts)))
    argument c t = case c of
      Convert x y
        | fits x t -> Right (sideType p y)
        | otherwise -> wrong ["NX-CONV-10"] (sideText x) t
      Trunc
        | Just e <- baseElem t, isAnyReal e -> Right (TElem DINT)
        | otherwise -> wrong ["NX-CONV-34"] "REAL or LREAL" t
      TruncInt
        | Just e <- baseElem t, isAnyReal e -> Right (TElem INT)
        | otherwise -> wrong ["NX-CONV-36"] "REAL or LREAL" t
      AnyTo numOnly y
        | Just x <- sourceSide t, not numOnly || isNumber x, x == y || convertible p x y -> Right (sideType p y)
        | otherwise -> wrong ["NX-TYPE-86"] (if numOnly then "number (ANY_NUM)" else "value of a type that converts to " <> sideText y) t
      BcdToInt src y
        | Just e <- baseElem t, maybe (isBitString e) (== e) src -> Right (TElem y)
        | otherwise -> wrong [] (maybe "bit string (BYTE, WORD, DWORD, LWORD)" elemName src) t
      IntToBcd x dst
        | baseElem t == Just x -> Right (TElem (fromMaybe (bcdElem x) dst))
        | otherwise -> wrong [] (elemName x) t
    fits x t = case x of
      CElem e -> baseElem t == Just e
      CString -> case t of
        TString False _ -> True
        _ -> False
    sourceSide t = case t of
      TString False _ -> Just CString
      _ -> CElem <$> baseElem t
    isNumber = \case
      CElem e -> isAnyNum e
      CString -> False
    -- the Nexto manual states what X_TO_Y, TRUNC, TRUNC_INT and ANY_TO_Y
    -- take; of the BCD conversions it gives only examples
    wrong nx what t = Left (name <> " converts a " <> what <> ", not a " <> typeText t <> " " <> citing p ("TC-CONV-6" : nx))

sideType :: Policies -> ConvType -> Type
sideType p = \case
  CElem e -> TElem e
  CString -> TString False (pStringLength p)

sideText :: ConvType -> Text
sideText = \case
  CElem e -> elemName e
  CString -> "STRING"

-- | The bit string of an integer type's width (TC-CONV-9: X_TO_BCD).
bcdElem :: Elem -> Elem
bcdElem x = case intBits x of
  8 -> BYTE
  16 -> WORD
  32 -> DWORD
  _ -> LWORD

------------------------------------------------------------------------
-- Meaning

-- | A conversion function applied (the argument types as checked).
conversion :: Policies -> Text -> [Type] -> [Value] -> Either Fault Value
conversion p name tys vs = case (conversionFunction p name, tys, vs) of
  (Just c, [t], [v]) -> case c of
    Convert _ y -> convert p t (sideType p y) v
    Trunc -> trunc p v
    TruncInt -> truncTo p INT v -- NX-CONV-36, NX-CONV-37
    AnyTo _ y -> convert p t (sideType p y) v -- NX-CONV-38: as X_TO_Y
    BcdToInt _ y -> bcdToInt p y v
    IntToBcd x dst -> intToBcd (fromMaybe (bcdElem x) dst) v
  _ -> Left (illTyped ("the conversion " <> name <> " of these arguments"))

-- | The value of type @to@ for a value of type @from@. Subranges convert as
-- their base types (the store checks the bounds: policy @subrange@); a
-- STRING result is the full text (the store applies the capacity: policy
-- @string-overflow@). Defined on every pair of 'convertible' and a few more
-- (the identity, BOOL with durations), so that the checker may insert a
-- conversion it allows implicitly; for pairs without a meaning (an
-- enumeration, DATE to INT) a 'Fault' of kind @conversion@.
--
-- * integer, bit string, duration to integer or bit string: the value if it
--   fits, else @narrow-int@ (TC-CONV-13, TC-CONV-14: also signed to
--   unsigned of the same width: INT_TO_UINT(-1) is 65535 under @wrap@, 0
--   under @saturate@);
-- * REAL, LREAL to integer, bit string or duration: 'realToInteger'
--   (TC-CONV-12);
-- * integer to REAL or LREAL: the nearest value, ties to even; LREAL to
--   REAL the same, and an infinity from a finite LREAL follows
--   @real-overflow@; REAL to LREAL exactly;
-- * BOOL to a number: 0 or 1; a number to BOOL: (x <> 0), so NaN is TRUE
--   and -0.0 FALSE;
-- * TIME to a number: its milliseconds, a number to TIME: milliseconds
--   (TC-CONV-16); LTIME the same in nanoseconds; TIME_TO_LTIME exact,
--   LTIME_TO_TIME truncated toward zero to milliseconds, then @narrow-int@;
-- * DT_TO_TOD the time of day, DT_TO_DATE the day at midnight (TC-CONV-10);
-- * to STRING: 'valueText'; from STRING: 'fromText' (TC-CONV-17);
-- * under @standard-library = codesys@, TOD, DATE and DT to and from BOOL
--   and the numbers through the number the controller stores ('dateNumber',
--   'numberDate').
convert :: Policies -> Type -> Type -> Value -> Either Fault Value
convert p from to v = case (side from, side to) of
  (Just _, Just CString) -> Right (VString (valueText p v))
  (Just _, Just (CElem y)) -> maybe none Right (toElem p y v)
  _ -> none
  where
    side = \case
      TElem e -> Just (CElem e)
      TSubrange e _ _ -> Just (CElem e)
      TString _ _ -> Just CString
      _ -> Nothing
    none = Left (Fault "conversion" ("no conversion from " <> typeText from <> " to " <> typeText to))

toElem :: Policies -> Elem -> Value -> Maybe Value
toElem p y v = case v of
  VBool b -> fromInt (if b then 1 else 0) -- NX-CONV-12, NX-CONV-15: TRUE is 1 in the type's unit
  VInt _ n -> fromInt n
  VReal r -> fromReal r r (float2Double r)
  VLReal r -> fromReal r (double2Float r) r
  VTime e n -> fromDuration e n
  VDT ms -> case y of
    DT -> Just v
    TOD -> Just (VTod (ms `mod` msPerDay)) -- TC-CONV-10
    DATE -> Just (VDate (ms - ms `mod` msPerDay))
    _ -> viaNumber
  VDate _ | y == DATE -> Just v
  VTod _ | y == TOD -> Just v
  VDate _ -> viaNumber
  VTod _ -> viaNumber
  VString s -> fromText p y s
  _ -> Nothing
  where
    codesys = codesysConversions p
    -- NX-CONV-26, NX-CONV-29: the number the controller stores, converted
    viaNumber
      | codesys = dateNumber v >>= fromInt
      | otherwise = Nothing
    fromInt n
      | y == BOOL = Just (VBool (n /= 0)) -- NX-CONV-16
      | y == REAL = Just (VReal (fromRational (fromInteger n)))
      | y == LREAL = Just (VLReal (fromRational (fromInteger n)))
      | isInt y || isDuration y = Just (integral y (narrowInt p y n))
      | codesys && isAnyDate y = Just (numberDate p y n)
      | otherwise = Nothing
    fromReal :: RealFloat a => a -> Float -> Double -> Maybe Value
    fromReal r asFloat asDouble
      | y == BOOL = Just (VBool (r /= 0))
      | y == REAL = Just (VReal (realOverflowFrom p (finite r) asFloat))
      | y == LREAL = Just (VLReal asDouble)
      -- an unsigned TIME (time-range) takes a real as a UDINT does
      | isInt y || isDuration y = Just (integral y (realToInteger (pRealToInt p) (if y == TIME && pTimeRange p == TimeUnsigned then UDINT else y) r))
      | codesys && isAnyDate y = Just (numberDate p y (realToInteger (pRealToInt p) DWORD r))
      | otherwise = Nothing
    fromDuration e n
      | y == e = Just v
      | y == LTIME = Just (VTime LTIME (narrowInt p LTIME (n * 1000000)))
      | y == TIME = Just (VTime TIME (narrowInt p TIME (n `quot` 1000000)))
      | otherwise = fromInt n

integral :: Elem -> Integer -> Value
integral y n = if isDuration y then VTime y n else VInt y n

-- | NX-TYPE-30..32, NX-CONV-26, NX-CONV-29 (standard-library = codesys):
-- the number a controller stores for a TOD (milliseconds since midnight),
-- a DATE or a DT (seconds since 1970-01-01; a DT's fraction of a second is
-- dropped: the values hold milliseconds, "Stref.IEC.Values").
dateNumber :: Value -> Maybe Integer
dateNumber = \case
  VTod ms -> Just ms
  VDate ms -> Just (ms `div` 1000)
  VDT ms -> Just (ms `div` 1000)
  _ -> Nothing

-- | The converse of 'dateNumber' (NX-CONV-10, NX-CONV-15): the number is
-- first made a DWORD (the types are "DWORDs internally", NX-TYPE-30) by
-- @narrow-int@; a TOD goes round modulo 24 hours as its arithmetic does
-- (TC-OP-60); a DATE is the midnight of the day the seconds fall in
-- (UDINT_TO_DATE(86400) = D#1970-01-02, and so is 90000).
numberDate :: Policies -> Elem -> Integer -> Value
numberDate p y n =
  let d = narrowInt p DWORD n
   in case y of
        TOD -> VTod (d `mod` msPerDay)
        DATE -> VDate ((d - d `mod` 86400) * 1000)
        _ -> VDT (d * 1000)

-- | An integer into a narrower (or differently signed) type (TC-CONV-13,
-- TC-CONV-14, policy @narrow-int@): the value if it fits, else the low bits
-- in two's complement (@wrap@) or the nearest bound (@saturate@).
narrowInt :: Policies -> Elem -> Integer -> Integer
narrowInt p y n
  | fitsUnder p y n = n
  | otherwise = case pNarrowInt p of
      NarrowWrap -> wrapUnder p y n
      NarrowSaturate -> let (lo, hi) = rangeUnder p y in max lo (min hi n)

-- | REAL or LREAL to an integer type (TC-CONV-12, policy @real-to-int@):
-- truncated toward zero or rounded to the nearest integer with ties to even
-- (2.5 -> 2, 3.5 -> 4, -2.5 -> -2), then clamped to the range
-- (@...-saturate@) or wrapped modulo 2^n (@round-even-wrap@). Decision
-- (open): NaN gives 0; +inf and -inf give the maximum and the minimum when
-- saturating, 0 when wrapping (every large binary value is a multiple of
-- 2^64, so 0 is the limit of the wrapped values).
realToInteger :: RealFloat a => RealToInt -> Elem -> a -> Integer
realToInteger policy y r
  | isNaN r = 0
  | isInfinite r = case policy of
      RoundEvenWrap -> 0
      _ -> if r > 0 then hi else lo
  | otherwise =
      let q = toRational r
       in case policy of
            TruncateSaturate -> max lo (min hi (truncate q))
            RoundEvenSaturate -> max lo (min hi (round q))
            RoundEvenWrap -> wrapInt y (round q)
  where
    (lo, hi) = intRange y

-- | TRUNC (TC-CONV-7): REAL or LREAL to DINT, truncated toward zero.
-- Decision: the result type is DINT (IEC ed.2 says ANY_INT, with no rule to
-- pick one); out of range and infinities are clamped, or wrapped under
-- @real-to-int=round-even-wrap@ (the saturate/wrap half of that policy);
-- NaN gives 0.
trunc :: Policies -> Value -> Either Fault Value
trunc p = truncTo p DINT

-- | TRUNC (NX-CONV-34) and TRUNC_INT (NX-CONV-36, NX-CONV-37): the integer
-- part, toward zero (TRUNC(-1.4) = -1), in the given integer type; beyond
-- it as 'trunc' says.
truncTo :: Policies -> Elem -> Value -> Either Fault Value
truncTo p y = \case
  VReal r -> Right (VInt y (go r))
  VLReal r -> Right (VInt y (go r))
  v -> Left (illTyped ("TRUNC of " <> renderValue v))
  where
    go :: RealFloat a => a -> Integer
    go r = case pRealToInt p of
      RoundEvenWrap
        | isNaN r || isInfinite r -> 0
        | otherwise -> wrapInt y (truncate (toRational r))
      _ -> realToInteger TruncateSaturate y r

-- | BCD_TO_Y (TC-CONV-8): the decimal digits held in the nibbles of a bit
-- string, e.g. 16#1234 -> 1234; then @narrow-int@ for Y's range. Decision
-- (TC-CONV-15, open): a nibble above 9 is a runtime error of kind
-- @conversion@.
bcdToInt :: Policies -> Elem -> Value -> Either Fault Value
bcdToInt p y = \case
  VInt _ x -> VInt y . narrowInt p y <$> digits x
  v -> Left (illTyped ("BCD_TO_" <> elemName y <> " of " <> renderValue v))
  where
    digits x
      | x <= 0 = Right 0
      | otherwise =
          let (q, d) = x `divMod` 16
           in if d > 9
                then Left (Fault "conversion" ("16#" <> T.pack (showHexInteger x) <> " holds a nibble that is no BCD digit"))
                else (\h -> h * 10 + d) <$> digits q

-- | X_TO_BCD (TC-CONV-9): the decimal digits of a non-negative integer in
-- the nibbles of the bit string @b@, e.g. 1234 -> 16#1234. Decision
-- (TC-CONV-15, open): a negative value or one with more digits than @b@ has
-- nibbles is a runtime error of kind @conversion@.
intToBcd :: Elem -> Value -> Either Fault Value
intToBcd b = \case
  VInt _ n
    | n < 0 -> Left (Fault "conversion" ("the negative value " <> T.pack (show n) <> " has no BCD code"))
    | length (show n) > intBits b `div` 4 -> Left (Fault "conversion" (T.pack (show n) <> " has more decimal digits than " <> elemName b <> " holds in BCD"))
    | otherwise -> Right (VInt b (foldl (\acc c -> acc * 16 + toInteger (digitToInt c)) 0 (show n)))
  v -> Left (illTyped ("the BCD conversion of " <> renderValue v))

showHexInteger :: Integer -> String
showHexInteger 0 = "0"
showHexInteger x = go x ""
  where
    go 0 acc = acc
    go n acc = let (q, d) = n `divMod` 16 in go q ("0123456789ABCDEF" !! fromInteger d : acc)

------------------------------------------------------------------------
-- Text

-- | X_TO_STRING (TC-CONV-17, open). Decision: BOOL as TRUE or FALSE;
-- integers and bit strings in decimal (WORD_TO_STRING(16#FF) = '255');
-- REAL and LREAL by 'realText'; TIME, DATE, TOD, DT as their literals
-- (@T#1h30m@, @D#2005-04-01@, @TOD#12:00:00.5@, @DT#2005-04-01-12:00:00@).
--
-- Under @standard-library = codesys@: at most 16 significant digits, the
-- 16th rounded (NX-CONV-25: LREAL 1.2345678901234567 gives
-- '1.234567890123457'); a DT whose seconds are 0 is written without them,
-- as the manual's DT_TO_STRING(DT#1998-02-13-14:20) =
-- 'DT#1998-02-13-14:20' (NX-CONV-30).
valueText :: Policies -> Value -> Text
valueText p = \case
  VBool b -> if b then "TRUE" else "FALSE"
  VInt _ n -> T.pack (show n)
  VReal r -> realNumber r
  VLReal r -> realNumber r
  VTime e n -> renderTime e n
  VDate ms -> renderDate ms
  VTod ms -> renderTod ms
  VDT ms
    | codesys && ms `mod` 60000 == 0 -> T.dropEnd 3 (renderDT ms) -- NX-CONV-30
    | otherwise -> renderDT ms
  VString s -> s
  VEnum _ n -> n
  v -> renderValue v
  where
    codesys = codesysConversions p
    realNumber :: RealFloat a => a -> Text
    realNumber
      | codesys = realTextDigits (Just 16) -- NX-CONV-25
      | otherwise = realText

-- | The shortest decimal that reads back as the same REAL (or LREAL):
-- fixed-point for magnitudes from 1E-5 up to below 1E+7 (@0.1@, @-2.5@,
-- @100.0@, @0.00001@), otherwise one digit before the point and an exponent
-- (@1.0E+7@, @1.5E-6@, @3.4028235E+38@); @0.0@, @-0.0@, @INF@, @-INF@,
-- @NAN@.
realText :: RealFloat a => a -> Text
realText = realTextDigits Nothing

-- | 'realText' with at most the given number of significant digits: a
-- shortest decimal with more is the value rounded to that many (the exact
-- binary value, ties to even), trailing zeros dropped.
realTextDigits :: RealFloat a => Maybe Int -> a -> Text
realTextDigits limit x
  | isNaN x = "NAN"
  | isInfinite x = if x > 0 then "INF" else "-INF"
  | x == 0 = if isNegativeZero x then "-0.0" else "0.0"
  | otherwise = T.pack ((if x < 0 then "-" else "") ++ body (limited (floatToDigits 10 (abs x))))
  where
    limited (ds, e) = case limit of
      Just k | length ds > k ->
        let m = round (toRational (abs x) * 10 ^^ (k - e)) :: Integer
            digits = map (\c -> fromEnum c - fromEnum '0') (show m)
         in if length digits > k
              then (dropZeros (take k digits), e + 1) -- rounded up to 10^k
              else (dropZeros digits, e)
      _ -> (ds, e)
    dropZeros ds = case reverse (dropWhile (== 0) (reverse ds)) of
      [] -> [0]
      r -> r
    body (ds0, e) =
      let ds = map (\d -> toEnum (fromEnum '0' + d)) ds0 :: String
          n = length ds
       in if e >= -4 && e <= 7
            then
              if e <= 0
                then "0." ++ replicate (negate e) '0' ++ ds
                else
                  if e >= n
                    then ds ++ replicate (e - n) '0' ++ ".0"
                    else take e ds ++ "." ++ drop e ds
            else
              let k = e - 1
                  rest = drop 1 ds
               in take 1 ds ++ "." ++ (if null rest then "0" else rest) ++ "E" ++ (if k < 0 then "-" else "+") ++ show (abs k)

-- | STRING to a number (TC-CONV-17, open). Decision: the whole text, blanks
-- around it ignored, must be a number, else the result is 0 (FALSE, 0.0):
--
-- * integers and bit strings: an optional sign and decimal digits, or
--   @2#@, @8#@, @16#@ and digits, single underscores between digits
--   allowed (the literal forms); out of range: @narrow-int@;
-- * REAL, LREAL: an optional sign, digits, an optional fraction, an
--   optional exponent (@E@ or @e@), rounded once; or @INF@, @-INF@, @NAN@
--   (what 'realText' writes); a finite text beyond the range follows
--   @real-overflow@;
-- * BOOL: @TRUE@ or @FALSE@ (any case), or an integer (TRUE when not 0);
-- * under @standard-library = codesys@, TIME, LTIME, TOD, DATE, DT: a
--   literal of the type, its prefix in any spelling (NX-CONV-33:
--   STRING_TO_TIME('T#127ms') = T#127ms; 'Stref.IEC.Parser.timeLiteral');
--   for TIME and LTIME a duration of either prefix (TIME keeps whole
--   milliseconds, LTIME nanoseconds, then @narrow-int@); otherwise the
--   type's zero
--   (NX-CONV-32).
fromText :: Policies -> Elem -> Text -> Maybe Value
fromText p y s
  | y == BOOL = Just (VBool (boolText s))
  | isInt y = Just (VInt y (narrowInt p y (fromMaybe 0 (parseIntegerText s))))
  | y == REAL = Just (VReal (fromRealText (parseRealText s)))
  | y == LREAL = Just (VLReal (fromRealText (parseRealText s)))
  | codesysConversions p && isTimeLike y = Just (fromMaybe (defaultValue (TElem y)) (timeLiteral s >>= timeText))
  | otherwise = Nothing
  where
    timeText (kind, ns) = case y of
      TIME | isDuration kind -> Just (VTime TIME (narrowInt p TIME (ns `quot` 1000000)))
      LTIME | isDuration kind -> Just (VTime LTIME (narrowInt p LTIME ns))
      DATE | kind == DATE -> Just (VDate (ns `div` 1000000))
      TOD | kind == TOD -> Just (VTod (ns `div` 1000000))
      DT | kind == DT -> Just (VDT (ns `div` 1000000))
      _ -> Nothing
    boolText t = case upperName (T.strip t) of
      "TRUE" -> True
      "FALSE" -> False
      _ -> maybe False (/= 0) (parseIntegerText t)
    fromRealText :: RealFloat a => Maybe RealText -> a
    fromRealText = \case
      Nothing -> 0
      Just RNaN -> 0 / 0
      Just (RInf neg) -> signed neg (1 / 0)
      Just (RNum neg q) -> signed neg (realOverflowFrom p True (fromRational q))
    signed neg z = if neg then negate z else z

-- | An integer in the forms of 'fromText'.
parseIntegerText :: Text -> Maybe Integer
parseIntegerText t0 = do
  let t = T.strip t0
  (neg, body) <- Just (sign t)
  n <- case T.splitOn "#" body of
    [ds] -> digitsIn 10 ds
    [b, ds]
      | b `elem` ["2", "8", "16"] -> digitsIn (read (T.unpack b)) ds
    _ -> Nothing
  Just (if neg then negate n else n)

sign :: Text -> (Bool, Text)
sign t = case T.uncons t of
  Just ('-', r) -> (True, r)
  Just ('+', r) -> (False, r)
  _ -> (False, t)

-- | Digits of a base with single underscores between them.
digitsIn :: Integer -> Text -> Maybe Integer
digitsIn base ds = do
  guard (not (T.null ds) && T.head ds /= '_' && T.last ds /= '_' && not ("__" `T.isInfixOf` ds))
  let xs = T.unpack (T.filter (/= '_') ds)
  guard (all (\c -> isHexDigit c && toInteger (digitToInt c) < base) xs)
  Just (foldl (\acc c -> acc * base + toInteger (digitToInt c)) 0 xs)

-- | A real in the forms of 'fromText': NaN, an infinity, or a sign and an
-- exact magnitude.
data RealText = RNaN | RInf Bool | RNum Bool Rational
  deriving (Eq, Show)

parseRealText :: Text -> Maybe RealText
parseRealText t0 = case upperName t of
  "NAN" -> Just RNaN
  "INF" -> Just (RInf False)
  "+INF" -> Just (RInf False)
  "-INF" -> Just (RInf True)
  _ -> do
    let (neg, body) = sign t
        (mant, ex) = T.break (\c -> c == 'E' || c == 'e') body
        (ip, fp) = T.break (== '.') mant
    i <- digitsIn 10 ip
    (f, fDigits) <- case T.uncons fp of
      Nothing -> Just (0, 0)
      Just (_, fr) -> (\v -> (v, T.length (T.filter isDigit fr))) <$> digitsIn 10 fr
    e <- case T.uncons ex of
      Nothing -> Just 0
      Just (_, er) -> let (en, eb) = sign er in (\v -> if en then negate v else v) <$> (guard (T.all isDigit eb) >> digitsIn 10 eb)
    let m = i * 10 ^ fDigits + f
        k = e - toInteger fDigits
        digitsOfM = toInteger (length (show m))
    Just $
      if m == 0
        then RNum neg 0
        else
          if k > 400
            then RNum neg (10 ^ (401 :: Int)) -- beyond every binary64: rounds to infinity
            else
              if k < negate (400 + digitsOfM)
                then RNum neg 0 -- below 10^-400: zero in every format
                else RNum neg (fromInteger m * (10 ^^ k))
  where
    t = T.strip t0
