-- | The operators of Structured Text on elementary values (Tecomat catalogue
-- §4; IEC 61131-3 ed.2 Tab.3.13-3.20): which operand types each operator
-- takes and what result type it gives ('binaryType', 'unaryType'), and what
-- it computes under the policies ('binary', 'unary').
--
-- Every meaning is exact first and then fitted to its type: integers and
-- times are computed on 'Integer' and then put into the type's range by the
-- @overflow@ policy; REAL is binary32 ('Float') and LREAL binary64
-- ('Double'), each operation rounded once (Haskell's 'Float' and 'Double'
-- operations are the correctly rounded IEEE 754 ones).
--
-- 'binary' and 'unary' are total: operands the checker would have rejected
-- give a 'Fault' of kind @internal@, which a checked program never meets.
module Stref.IEC.Operators
  ( -- * Typing
    binaryType
  , unaryType
  , unOpSymbol
    -- * Meaning
  , binary
  , binaryWhy
  , unary
  , binaryOverflows
  , unaryOverflows
    -- * Shared with the standard functions and the conversions
  , intResult
  , inRange
  , rangeUnder
  , fitsUnder
  , wrapUnder
  , realOverflow
  , realOverflowFrom
  , finite
  , maxFinite
  , divisionByZero
  , illTyped
  , divideInt
  , moduloInt
  , strip
  ) where

import Control.Applicative ((<|>))
import Data.Bits (complement, xor, (.&.), (.|.))
import Data.Text (Text)
import qualified Data.Text as T
import GHC.Float (double2Float, float2Double)
import Stref.IEC.Syntax (BinOp (..), UnOp (..), binOpSymbol)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Stref.Trace (Decision, ruled)

------------------------------------------------------------------------
-- Typing

-- | The result type of @a op b@, or why the operator does not apply
-- (TC-OP-7: an operator takes what the corresponding function of
-- Tab.3.14-3.20 takes). A subrange stands for its base type, and so does
-- the result. Apart from the rows of Tab.3.20 and the exponent of @**@,
-- both operands have one type (TC-CONV-1).
--
-- @arith-width@ does not enter the typing: under @promote-32@ too the
-- result has the operands' type (TC-CONV-2); only the intermediate width
-- would differ, and this reference computes exactly (see 'intResult').
binaryType :: Policies -> BinOp -> Type -> Type -> Either Text Type
binaryType pol op ta tb = case typeOf op a b <|> bitArithmetic of
  Just t -> Right t
  Nothing
    | a /= b && (isJust' (typeOf op a a) || isJust' (typeOf op b b)) ->
        Left ("the operands of " <> quoted <> " have different types, " <> typeText ta <> " and " <> typeText tb <> "; convert one explicitly " <> citing pol ["TC-CONV-1", "NX-CONV-1", "NX-CONV-2"])
    | otherwise -> Left ("the operator " <> quoted <> " is not defined on " <> typeText ta <> " and " <> typeText tb)
  where
    a = strip ta
    b = strip tb
    quoted = "'" <> binOpSymbol op <> "'"
    isJust' = maybe False (const True)
    -- NX-OP-23, NX-OP-30: policy bit-string-arithmetic
    bitArithmetic = case (a, b) of
      (TElem x, TElem y)
        | x == y, isBitString x, op `elem` [BAdd, BSub, BMul, BDiv, BMod], pBitStringArithmetic pol == BitArithmeticYes -> Just a
      _ -> Nothing

-- | A subrange is its base type for the operators (TC-TYPE-29).
strip :: Type -> Type
strip = \case
  TSubrange e _ _ -> TElem e
  t -> t

typeOf :: BinOp -> Type -> Type -> Maybe Type
typeOf op a b = case op of
  BAdd -> same isAnyNum <|> addTime <|> concatenation -- TC-OP-12, TC-OP-49..51, TC-OP-9
  BSub -> same isAnyNum <|> subTime -- TC-OP-14, TC-OP-52..57
  BMul -> same isAnyNum <|> scaleTime -- TC-OP-13, TC-OP-58
  BDiv -> same isAnyNum <|> scaleTime -- TC-OP-15, TC-OP-59
  -- TC-OP-11, TC-OP-16 (open): Tab.3.14 types MOD as ANY_NUM; decision:
  -- MOD is also defined on REAL and LREAL, with the sign of the dividend
  -- like C's fmod (see 'binary').
  BMod -> same isAnyNum
  BPow -> power -- TC-OP-17, TC-OP-25
  BLt -> ordered
  BGt -> ordered
  BLe -> ordered
  BGe -> ordered
  BEq -> ordered <|> enumeration -- TC-OP-45, TC-TYPE-36
  BNe -> ordered <|> enumeration
  BAnd -> same isAnyBit -- TC-OP-38, TC-OP-39
  BOr -> same isAnyBit
  BXor -> same isAnyBit
  where
    same f = case (a, b) of
      (TElem x, TElem y) | x == y, f x -> Just a
      _ -> Nothing
    bool = TElem BOOL
    -- TC-OP-45, TC-OP-46: comparisons on one elementary type or on strings
    -- (of any capacities); not on enumerations (TC-TYPE-36)
    ordered = (bool <$ same (\e -> isAnyNum e || isAnyBit e || isTimeLike e)) <|> (bool <$ strings)
    strings = case (a, b) of
      (TString w1 _, TString w2 _) | w1 == w2 -> Just a
      _ -> Nothing
    enumeration = case (a, b) of
      (TEnum {}, TEnum {}) | a == b -> Just bool
      _ -> Nothing
    -- TC-OP-9: STRING + STRING; the capacity of the result holds both
    concatenation = case (a, b) of
      (TString w1 n1, TString w2 n2) | w1 == w2 -> Just (TString w1 (min maxStringLength (n1 + n2)))
      _ -> Nothing
    elems = case (a, b) of
      (TElem x, TElem y) -> Just (x, y)
      _ -> Nothing
    addTime =
      elems >>= \case
        (TIME, TIME) -> Just (TElem TIME) -- TC-OP-49
        (LTIME, LTIME) -> Just (TElem LTIME)
        (TOD, TIME) -> Just (TElem TOD) -- TC-OP-50
        (DT, TIME) -> Just (TElem DT) -- TC-OP-51
        _ -> Nothing
    subTime =
      elems >>= \case
        (TIME, TIME) -> Just (TElem TIME) -- TC-OP-52
        (LTIME, LTIME) -> Just (TElem LTIME)
        (DATE, DATE) -> Just (TElem TIME) -- TC-OP-53
        (TOD, TIME) -> Just (TElem TOD) -- TC-OP-54
        (TOD, TOD) -> Just (TElem TIME) -- TC-OP-55
        (DT, TIME) -> Just (TElem DT) -- TC-OP-56
        (DT, DT) -> Just (TElem TIME) -- TC-OP-57
        _ -> Nothing
    -- TC-OP-58, TC-OP-59, TC-CONV-5: TIME * ANY_NUM, TIME / ANY_NUM (the
    -- duration on the left, as in Tab.3.20)
    scaleTime =
      elems >>= \case
        (t, n) | t `elem` [TIME, LTIME], isAnyNum n -> Just (TElem t)
        _ -> Nothing
    -- TC-OP-17, TC-OP-25: a REAL base takes any ANY_NUM exponent, an
    -- integer base an integer exponent; the result has the base's type.
    power =
      elems >>= \case
        (x, y)
          | isAnyReal x && isAnyNum y -> Just a
          | isAnyInt x && isAnyInt y -> Just a
        _ -> Nothing

-- | TC-OP-1: unary @-@ on the signed integers, the reals and the durations;
-- @NOT@ on ANY_BIT (TC-OP-38); unary @+@ on ANY_NUM.
unaryType :: UnOp -> Type -> Either Text Type
unaryType op t = case (op, strip t) of
  (UNeg, TElem e) | isSignedInt e || isAnyReal e || e == TIME || e == LTIME -> Right (TElem e)
  (UNot, TElem e) | isAnyBit e -> Right (TElem e)
  (UPlus, TElem e) | isAnyNum e -> Right (TElem e)
  _ -> Left ("the operator '" <> unOpSymbol op <> "' is not defined on " <> typeText t)

unOpSymbol :: UnOp -> Text
unOpSymbol = \case
  UNeg -> "-"
  UNot -> "NOT"
  UPlus -> "+"

-- | The longest string: STRING[n] takes n up to 65535.
maxStringLength :: Int
maxStringLength = 65535

------------------------------------------------------------------------
-- Meaning

-- | @a op b@ on values of the types 'binaryType' accepts.
binary :: Policies -> BinOp -> Value -> Value -> Either Fault Value
binary p BPow a b = power p a b
binary p op a b = case (a, b) of
  (VInt e x, VInt e' y) | e == e' -> intBinary p op e x y
  (VReal x, VReal y) -> realBinary p VReal op x y
  (VLReal x, VLReal y) -> realBinary p VLReal op x y
  (VBool x, VBool y) -> boolBinary op x y
  (VString x, VString y) -> stringBinary op x y
  (VEnum t x, VEnum t' y) | upperName t == upperName t' -> enumBinary op x y
  _ -> timeBinary p op a b

-- | 'binary' with the rules that decided its outcome where a policy did
-- (integer overflow, division and MOD by zero): what a trace shows. Apart
-- from 'binary', which an untraced run calls and which then builds none
-- of it.
binaryWhy :: Policies -> BinOp -> Value -> Value -> (Either Fault Value, [Decision])
binaryWhy p op a b = (r, why)
  where
    r = binary p op a b
    why = case (a, b) of
      (VInt e x, VInt e' y) | e == e' -> intDecisions p op e x y r
      (VReal x, VReal y) -> realWhy x y
      (VLReal x, VLReal y) -> realWhy x y
      (VTime e x, VTime e' y) | e == e', op == BAdd -> durationWhy "TC-OP-49" e (x + y)
      (VTime e x, VTime e' y) | e == e', op == BSub -> durationWhy "TC-OP-52" e (x - y)
      (VDate x, VDate y) | op == BSub -> durationWhy "TC-OP-53" TIME (x - y)
      (VTod x, VTod y) | op == BSub -> durationWhy "TC-OP-55" TIME (x - y)
      (VDT x, VDT y) | op == BSub -> durationWhy "TC-OP-57" TIME (x - y)
      (VTime e x, n) | op `elem` [BMul, BDiv] -> scaleWhy e x n
      _ -> []
    outcome = either (const "a runtime error") (\v -> "the result is " <> renderValue v) r
    written = renderValue a <> " " <> binOpSymbol op <> " " <> renderValue b
    -- the decisions of REAL arithmetic: an infinite result of finite
    -- operands (TC-OP-26, real-overflow), a division by zero (TC-OP-22,
    -- real-div-zero)
    realWhy x y
      | op == BDiv, y == 0 = [ruled ["TC-OP-22", "TC-OP-26", "NX-ERR-10"] "real-div-zero" (written <> ": division by zero gives " <> either (const "a runtime error") renderValue r)]
      | Just exact <- realArith op x y, finite x, finite y, isInfinite exact =
          [ruled ["TC-OP-26"] "real-overflow" (written <> " leaves the range of " <> describe a <> ": " <> outcome)]
      | otherwise = []
    -- a duration outside its range, from a sum or difference of durations,
    -- a difference of dates or times of day, or a duration scaled (the
    -- operator's rule): the overflow policy over the range time-range
    -- gives (TC-TYPE-19, NX-TYPE-30, NX-TYPE-34)
    durationWhy rule e n
      | fitsUnder p e n = []
      | otherwise = [ruled [rule, "TC-TYPE-19", "NX-TYPE-30", "NX-TYPE-34"] "overflow" (written <> " lies outside " <> elemName e <> " (time-range=" <> timeRangeName <> "): " <> outcome)]
    -- a duration times or divided by a number (TC-OP-58, TC-OP-59): by zero
    -- follows div-zero, an exact result outside the range overflow
    scaleWhy e x = \case
      VInt _ k
        | op == BDiv, k == 0 -> divZeroWhy
        | otherwise -> durationWhy scaleRule e (if op == BMul then x * k else x `quot` k)
      VReal f -> byReal (realToFrac f :: Double)
      VLReal d -> byReal d
      _ -> []
      where
        byReal r
          | isNaN r || (isInfinite r && (op == BDiv || x == 0)) = []
          | op == BDiv, r == 0 = divZeroWhy
          | isInfinite r = [ruled [scaleRule, "TC-TYPE-19", "NX-TYPE-30"] "overflow" (written <> " is infinite, outside " <> elemName e <> ": " <> outcome)]
          | op == BMul = durationWhy scaleRule e (truncate (fromInteger x * toRational r))
          | otherwise = durationWhy scaleRule e (truncate (fromInteger x / toRational r))
    scaleRule = if op == BMul then "TC-OP-58" else "TC-OP-59"
    divZeroWhy = [ruled ["TC-OP-22", "TC-OP-59", "NX-OP-29"] "div-zero" (written <> ": division by zero " <> either (const "is a runtime error") (\v -> "gives " <> renderValue v) r)]
    timeRangeName = if pTimeRange p == TimeUnsigned then "unsigned" else "signed"

-- | Integers (ANY_INT) and bit strings (ANY_BIT without BOOL).
intBinary :: Policies -> BinOp -> Elem -> Integer -> Integer -> Either Fault Value
intBinary p op e x y = case exactInt p op x y of
  Just n -> intResult p e n
  Nothing -> case op of
    BDiv -> divisionByZero p (VInt e 0) -- TC-OP-22 (y = 0)
    BMod -> case pModZero p of -- TC-OP-24 (y = 0)
      ModZeroZero -> Right (VInt e 0)
      ModZeroError -> Left (Fault "division-by-zero" "MOD by zero")
    BAnd -> Right (VInt e (x .&. y)) -- TC-OP-39: bit by bit
    BOr -> Right (VInt e (x .|. y))
    BXor -> Right (VInt e (x `xor` y))
    _ -> VBool <$> compareWith op x y

-- | The exact result of an arithmetic operator on integers, before it is
-- fitted into the type ('intResult'); none for the other operators and for
-- a zero divisor.
exactInt :: Policies -> BinOp -> Integer -> Integer -> Maybe Integer
exactInt p op x y = case op of
  BAdd -> Just (x + y)
  BSub -> Just (x - y)
  BMul -> Just (x * y)
  -- TC-OP-21: truncation toward zero (mod-sign=dividend) or the floor of
  -- the euclidean division; only the most negative value / -1 leaves the
  -- range, and then the overflow policy decides.
  BDiv | y /= 0 -> Just (divideInt (pModSign p) x y)
  BMod | y /= 0 -> Just (moduloInt (pModSign p) x y) -- TC-OP-23
  _ -> Nothing
{-# INLINE exactInt #-}

-- | What decided an integer operator's result @r@: division or MOD by
-- zero, or an exact result that left the type (TC-OP-20, NX-OP-32; a bit
-- string has no overflow).
intDecisions :: Policies -> BinOp -> Elem -> Integer -> Integer -> Either Fault Value -> [Decision]
intDecisions p op e x y r = case op of
  BDiv | y == 0 -> [ruled ["TC-OP-22", "NX-OP-29"] "div-zero" (expression <> ": division by zero " <> failsOr "gives 0")]
  BMod | y == 0 -> [ruled ["TC-OP-24", "NX-DIFF-8"] "mod-zero" (expression <> ": MOD by zero " <> failsOr "gives 0")]
  _ -> case exactInt p op x y of
    Just n
      | left n && not (isBitString e) ->
          [ruled ["TC-OP-20", "NX-OP-32", "NX-ERR-24"] "overflow" (expression <> " = " <> T.pack (show n) <> " lies outside " <> elemName e <> ": " <> either (const "a runtime error") (\v -> "the result is " <> renderValue v) r)]
    _ -> []
  where
    expression = T.pack (show x) <> " " <> binOpSymbol op <> " " <> T.pack (show y)
    failsOr what = either (const "is a runtime error") (const what) r
    left n = case r of
      Right (VInt _ m) -> m /= n
      _ -> True

-- | The quotient: truncated toward zero (@mod-sign=dividend@, TC-OP-21) or
-- euclidean (the remainder is never negative). Always
-- @x = y * divideInt s x y + moduloInt s x y@. The divisor is not zero.
divideInt :: ModSign -> Integer -> Integer -> Integer
divideInt ModSignDividend x y = x `quot` y
divideInt ModSignEuclidean x y = (x - moduloInt ModSignEuclidean x y) `div` y

-- | The remainder (TC-OP-23): the sign of the dividend, or euclidean
-- (@0 <= r < |y|@).
moduloInt :: ModSign -> Integer -> Integer -> Integer
moduloInt ModSignDividend x y = x `rem` y
moduloInt ModSignEuclidean x y = x `mod` abs y

-- | An exact integer result fitted into its type (TC-OP-20, policy
-- @overflow@): kept when it fits; else clamped to the range (@saturate@),
-- reduced modulo 2^n in two's complement (@wrap@) or a runtime error of kind
-- @overflow@ (@trap@).
--
-- Decision: bit strings (BYTE, WORD, DWORD, LWORD) have no overflow; a
-- result on a bit string always wraps modulo 2^n, whatever the policy.
-- (The checker admits no arithmetic on bit strings, Tab.3.14 being ANY_NUM;
-- the rule serves shifts, NOT and robustness.)
--
-- @arith-width=promote-32@ is not modelled here: the result is computed
-- exactly and then fitted to the operands' type, which is what promote-32
-- gives whenever the exact result fits 32 bits (every + - * of SINT, INT,
-- USINT, UINT operands does).
intResult :: Policies -> Elem -> Integer -> Either Fault Value
intResult p e n
  | isBitString e = Right (VInt e (wrapInt e n))
  -- arith-width = promote-32: an operand narrower than 32 bits is computed
  -- in DINT, as C does; the value is narrowed when it is stored
  | pArithWidth p == Promote32, isAnyInt e, intBits e < 32 = VInt e <$> inRange p DINT n
  | otherwise = VInt e <$> inRange p e n

-- | 'intResult' without the value constructor; for TIME and LTIME too.
inRange :: Policies -> Elem -> Integer -> Either Fault Integer
inRange p e n
  | fitsUnder p e n = Right n
  | otherwise = case pOverflow p of
      Saturate -> Right (max lo (min hi n))
      Wrap -> Right (wrapUnder p e n)
      Trap -> Left (Fault "overflow" ("the result " <> T.pack (show n) <> " is outside the range of " <> elemName e))
  where
    (lo, hi) = rangeUnder p e

-- | The values of a type under the policies: TIME's range is policy
-- @time-range@'s, signed (TC-TYPE-19) or a DWORD's (NX-TYPE-30); every
-- other type's is its own.
rangeUnder :: Policies -> Elem -> (Integer, Integer)
rangeUnder p e
  | e == TIME && pTimeRange p == TimeUnsigned = intRange DWORD
  | otherwise = intRange e

fitsUnder :: Policies -> Elem -> Integer -> Bool
fitsUnder p e n = let (lo, hi) = rangeUnder p e in lo <= n && n <= hi

-- | The low bits of a value, read in the type's range under the policies.
wrapUnder :: Policies -> Elem -> Integer -> Integer
wrapUnder p e n
  | e == TIME && pTimeRange p == TimeUnsigned = wrapInt DWORD n
  | otherwise = wrapInt e n

-- | Integer or duration division by zero (TC-OP-22, policy @div-zero@):
-- a runtime error of kind @division-by-zero@ (@error@ and @trap@ alike), or
-- the given zero.
divisionByZero :: Policies -> Value -> Either Fault Value
divisionByZero p zero = case pDivZero p of
  DivZeroZero -> Right zero
  _ -> Left (Fault "division-by-zero" "division by zero")

-- | Comparisons on a totally or IEEE-ordered type: the operators of 'Ord'
-- are IEEE's on 'Float' and 'Double' (a NaN operand makes every comparison
-- FALSE except @<>@).
compareWith :: Ord a => BinOp -> a -> a -> Either Fault Bool
compareWith op x y = case op of
  BLt -> Right (x < y)
  BGt -> Right (x > y)
  BLe -> Right (x <= y)
  BGe -> Right (x >= y)
  BEq -> Right (x == y)
  BNe -> Right (x /= y)
  _ -> Left (illTyped ("the operator " <> binOpSymbol op <> " on these operands"))

-- | REAL (binary32) and LREAL (binary64) arithmetic, each operation rounded
-- once to the type.
realBinary :: RealFloat a => Policies -> (a -> Value) -> BinOp -> a -> a -> Either Fault Value
realBinary p mk op x y = case op of
  BDiv
    | y == 0 -> case pRealDivZero p of -- TC-OP-22, TC-OP-26
        RealDivZeroError -> Left (Fault "division-by-zero" "REAL division by zero")
        RealDivZeroIeee -> Right (mk (x / y)) -- ±inf, or NaN for 0.0/0.0
  BMod -> realMod p mk x y
  _ -> case realArith op x y of
    Just r -> Right (mk (realOverflow p [x, y] r))
    Nothing -> VBool <$> compareWith op x y

-- | The IEEE result of + - * / in the operands' format, before the
-- overflow policy.
realArith :: RealFloat a => BinOp -> a -> a -> Maybe a
realArith op x y = case op of
  BAdd -> Just (x + y)
  BSub -> Just (x - y)
  BMul -> Just (x * y)
  BDiv -> Just (x / y)
  _ -> Nothing

-- | TC-OP-26 (policy @real-overflow@): an infinite result of finite operands
-- is an overflow; @saturate@ replaces it by the largest finite value of its
-- sign, @ieee@ keeps the infinity. Infinite or NaN operands propagate by
-- IEEE rules.
realOverflow :: RealFloat a => Policies -> [a] -> a -> a
realOverflow p operands = realOverflowFrom p (all finite operands)

-- | 'realOverflow' with the finiteness of the operands given.
realOverflowFrom :: RealFloat a => Policies -> Bool -> a -> a
realOverflowFrom p finiteOperands r
  | isInfinite r && finiteOperands = case pRealOverflow p of
      RealOverflowSaturate -> if r > 0 then maxFinite r else negate (maxFinite r)
      RealOverflowIeee -> r
  | otherwise = r

finite :: RealFloat a => a -> Bool
finite z = not (isNaN z || isInfinite z)

-- | The largest finite value of the argument's format (3.4028235e38 for
-- 'Float', 1.7976931348623157e308 for 'Double').
maxFinite :: RealFloat a => a -> a
maxFinite r =
  let d = floatDigits r
      (_, hi) = floatRange r
   in encodeFloat (2 ^ d - 1) (hi - d)

-- | REAL MOD (TC-OP-11 decision): @x - y * TRUNC(x / y)@ exactly, as C's
-- @fmod@ (the remainder has the sign of the dividend and is exact); under
-- @mod-sign=euclidean@ a negative remainder gets @|y|@ added, rounded
-- once. @x MOD 0.0@ follows @mod-zero@ like the integers (TC-OP-24). An
-- infinite or NaN dividend or a NaN divisor gives NaN; an infinite divisor
-- gives the dividend.
realMod :: RealFloat a => Policies -> (a -> Value) -> a -> a -> Either Fault Value
realMod p mk x y
  | y == 0 = case pModZero p of
      ModZeroZero -> Right (mk 0)
      ModZeroError -> Left (Fault "division-by-zero" "MOD by zero")
  | isNaN x || isNaN y || isInfinite x = Right (mk (0 / 0))
  | isInfinite y = Right (mk (euclid x))
  | otherwise =
      let qx = toRational x
          qy = toRational y
          r = qx - qy * fromInteger (truncate (qx / qy))
          signed = if r == 0 then (if x < 0 || isNegativeZero x then -0 else 0) else fromRational r
       in Right (mk (euclid signed))
  where
    euclid r = case pModSign p of
      ModSignEuclidean | r < 0 -> r + abs y
      _ -> r

-- | FALSE < TRUE (ANY_BIT is ordered, TC-OP-45); AND, OR, XOR are logical
-- on BOOL (TC-OP-39).
boolBinary :: BinOp -> Bool -> Bool -> Either Fault Value
boolBinary op x y = case op of
  BAnd -> Right (VBool (x && y))
  BOr -> Right (VBool (x || y))
  BXor -> Right (VBool (x /= y))
  _ -> VBool <$> compareWith op x y

-- | TC-OP-9: @+@ concatenates; TC-OP-46, TC-OP-47: strings compare
-- character by character by code (case-sensitive), and a proper prefix is
-- smaller than the string it begins (as C's strcmp: NUL is below every
-- character). 'Text' ordering is exactly that for codes 0-255.
stringBinary :: BinOp -> Text -> Text -> Either Fault Value
stringBinary op x y = case op of
  BAdd -> Right (VString (T.take maxStringLength (x <> y)))
  _ -> VBool <$> compareWith op x y

-- | TC-TYPE-36: only = and <> on enumerated values.
enumBinary :: BinOp -> Text -> Text -> Either Fault Value
enumBinary op x y = case op of
  BEq -> Right (VBool (upperName x == upperName y))
  BNe -> Right (VBool (upperName x /= upperName y))
  _ -> Left (illTyped ("the operator " <> binOpSymbol op <> " on enumerated values"))

-- | Tab.3.20 (TC-OP-48..62). TIME counts milliseconds in 32 signed bits
-- (TC-TYPE-19) and its results go through the @overflow@ policy like an
-- integer's; LTIME counts nanoseconds in 64 bits. A TOD result wraps modulo
-- 24 h (TC-OP-60). DATE and DT are milliseconds since 1970-01-01 with no
-- upper bound (TC-TYPE-20), computed exactly. Negative durations are
-- ordinary values (TC-OP-61). Note: a difference of dates or DTs more than
-- 24d20h31m23s647ms apart leaves the TIME range and overflows.
timeBinary :: Policies -> BinOp -> Value -> Value -> Either Fault Value
timeBinary p op a b = case (a, b) of
  (VTime e x, VTime e' y) | e == e' -> case op of
    BAdd -> duration e (x + y) -- TC-OP-49
    BSub -> duration e (x - y) -- TC-OP-52
    _ -> VBool <$> compareWith op x y
  (VTod x, VTime TIME y) -> case op of
    BAdd -> Right (VTod ((x + y) `mod` msPerDay)) -- TC-OP-50, TC-OP-60
    BSub -> Right (VTod ((x - y) `mod` msPerDay)) -- TC-OP-54, TC-OP-60
    _ -> bad
  (VDT x, VTime TIME y) -> case op of
    BAdd -> Right (VDT (x + y)) -- TC-OP-51
    BSub -> Right (VDT (x - y)) -- TC-OP-56
    _ -> bad
  (VDate x, VDate y) -> difference x y -- TC-OP-53
  (VTod x, VTod y) -> difference x y -- TC-OP-55
  (VDT x, VDT y) -> difference x y -- TC-OP-57
  (VTime e x, n) | op == BMul || op == BDiv -> scaleTime p op e x n
  _ -> bad
  where
    duration e n = VTime e <$> inRange p e n
    difference x y = case op of
      BSub -> duration TIME (x - y)
      _ -> VBool <$> compareWith op x y
    bad = Left (illTyped ("the operator " <> binOpSymbol op <> " on " <> describe a <> " and " <> describe b))

-- | TC-OP-58, TC-OP-59, TC-OP-62: a duration times or divided by a number.
-- By an integer: the exact product, or the quotient truncated toward zero
-- (whatever @mod-sign@ says: TC-OP-62); then the duration's range under
-- @overflow@. By a REAL or LREAL: the exact product or quotient of the
-- binary values, truncated toward zero, then the range. Division by zero
-- (integer or real) follows @div-zero@ (the result is a TIME, which has no
-- infinity). A NaN factor gives T#0s, and so does 0 * inf and any / inf;
-- another infinite result is an overflow: the limit of its sign under
-- @saturate@, T#0s under @wrap@, an error under @trap@.
scaleTime :: Policies -> BinOp -> Elem -> Integer -> Value -> Either Fault Value
scaleTime p op e x n = case n of
  VInt _ k
    | op == BMul -> duration (x * k)
    | k == 0 -> divisionByZero p (VTime e 0)
    | otherwise -> duration (x `quot` k)
  VReal r -> byReal r
  VLReal r -> byReal r
  _ -> Left (illTyped ("a duration " <> binOpSymbol op <> " " <> describe n))
  where
    duration v = VTime e <$> inRange p e v
    byReal :: RealFloat a => a -> Either Fault Value
    byReal r
      | isNaN r = Right (VTime e 0)
      | op == BDiv && r == 0 = divisionByZero p (VTime e 0)
      | isInfinite r = if op == BDiv || x == 0 then Right (VTime e 0) else infinite (signum x * (if r > 0 then 1 else -1))
      | op == BMul = duration (truncate (fromInteger x * toRational r))
      | otherwise = duration (truncate (fromInteger x / toRational r))
    infinite s = case pOverflow p of
      Saturate -> let (lo, hi) = intRange e in Right (VTime e (if s > 0 then hi else lo))
      Wrap -> Right (VTime e 0)
      Trap -> Left (Fault "overflow" ("an infinite duration is outside the range of " <> elemName e))

-- | @**@ and EXPT (TC-OP-17, TC-OP-25; TC-ERRATA-1).
--
-- Integer base and exponent: the exact power, then the @overflow@ policy of
-- the base's type. A negative exponent gives @1 / b^-e@ truncated toward
-- zero: 1 for b = 1, ±1 for b = -1, 0 for every other b, and for b = 0 the
-- integer division by zero of @div-zero@.
--
-- REAL base: @x ** y@ is computed in binary64 (C's @pow@) and rounded once
-- to binary32; LREAL in binary64. The exponent may be any ANY_NUM value.
-- @0.0 ** y@ with y < 0 is a division by zero (IEEE's pole): an error under
-- @real-div-zero=error@, ±inf under @ieee@. Otherwise an infinite result of
-- finite operands follows @real-overflow@.
power :: Policies -> Value -> Value -> Either Fault Value
power p a b = case (a, b) of
  (VInt e x, VInt _ k) -> intPower p e x k
  (VReal x, _) | Just y <- asDouble b -> VReal <$> realPower double2Float (float2Double x) y
  (VLReal x, _) | Just y <- asDouble b -> VLReal <$> realPower id x y
  _ -> Left (illTyped ("** on " <> describe a <> " and " <> describe b))
  where
    asDouble = \case
      VInt _ k -> Just (fromInteger k)
      VReal y -> Just (float2Double y)
      VLReal y -> Just y
      _ -> Nothing
    realPower :: RealFloat a => (Double -> a) -> Double -> Double -> Either Fault a
    realPower narrow x y
      | x == 0 && y < 0 = case pRealDivZero p of
          RealDivZeroError -> Left (Fault "division-by-zero" "0.0 raised to a negative power")
          RealDivZeroIeee -> Right (narrow (x ** y))
      | otherwise = Right (realOverflowFrom p (finite x && finite y) (narrow (x ** y)))

intPower :: Policies -> Elem -> Integer -> Integer -> Either Fault Value
intPower p e x k
  | k < 0 = case x of
      0 -> divisionByZero p (VInt e 0)
      1 -> Right (VInt e 1)
      -1 -> Right (VInt e (if even k then 1 else -1))
      _ -> Right (VInt e 0)
  -- |x| >= 2 and k > 128: beyond every range of 64 bits or less, computed
  -- without the huge exact power
  | abs x >= 2 && k > 128 =
      if isBitString e || pOverflow p == Wrap
        then Right (VInt e (wrapInt e (powMod x k (2 ^ intBits e))))
        else case pOverflow p of
          Trap -> Left (Fault "overflow" ("the power is outside the range of " <> elemName e))
          _ -> let (lo, hi) = intRange e in Right (VInt e (if x < 0 && odd k then lo else hi))
  | otherwise = intResult p e (x ^ k)
  where
    powMod _ 0 m = 1 `mod` m
    powMod b n m
      | even n = let h = powMod b (n `div` 2) m in (h * h) `mod` m
      | otherwise = (b * powMod b (n - 1) m) `mod` m

-- | Unary operators (TC-OP-1). Minus of the most negative integer (or
-- duration) is an overflow under the @overflow@ policy; minus of a REAL
-- flips its sign (also of 0.0 and NaN). NOT is logical on BOOL and bitwise
-- on bit strings (TC-OP-39).
unary :: Policies -> UnOp -> Value -> Either Fault Value
unary p op v = case (op, v) of
  (UNeg, VInt e x) -> intResult p e (negate x)
  (UNeg, VReal x) -> Right (VReal (negate x))
  (UNeg, VLReal x) -> Right (VLReal (negate x))
  (UNeg, VTime e x) -> VTime e <$> inRange p e (negate x)
  (UNot, VBool b) -> Right (VBool (not b))
  (UNot, VInt e x) -> Right (VInt e (wrapInt e (complement x)))
  (UPlus, VInt _ _) -> Right v
  (UPlus, VReal _) -> Right v
  (UPlus, VLReal _) -> Right v
  (UPlus, VTime _ _) -> Right v
  _ -> Left (illTyped ("the operator " <> unOpSymbol op <> " on " <> describe v))

-- | MT-OP-7 (policy @overflow-flag@): did @a op b@ overflow? 'Just' for the
-- operations an overflow flag follows, + - * and EXPT (@**@) on numbers,
-- whether the exact result left the range the @overflow@ policy fitted it
-- into (DINT's for a narrower operand under @promote-32@), or whether a REAL
-- result of finite operands is infinite (@real-overflow@); 'Nothing' for
-- the other operators and operands, which leave the flag. Arithmetic on a
-- bit string never overflows (it wraps, 'intResult').
binaryOverflows :: Policies -> BinOp -> Value -> Value -> Maybe Bool
binaryOverflows p op a b = case (a, b) of
  (VInt e x, VInt _ y)
    | op `elem` [BAdd, BSub, BMul] -> intOverflows p e <$> exactInt p op x y
    | op == BPow -> Just (y >= 0 && intOverflows p e (if abs x >= 2 && y > 128 then 2 ^ (129 :: Int) else x ^ y))
  (VReal x, VReal y) | op `elem` [BAdd, BSub, BMul] -> realOverflows <$> realArith op x y <*> pure [x, y]
  (VLReal x, VLReal y) | op `elem` [BAdd, BSub, BMul] -> realOverflows <$> realArith op x y <*> pure [x, y]
  (VReal x, _) | op == BPow, Just y <- asDouble b -> Just (powerOverflows double2Float (float2Double x) y)
  (VLReal x, _) | op == BPow, Just y <- asDouble b -> Just (powerOverflows id x y)
  _ -> Nothing
  where
    realOverflows r operands = isInfinite r && all finite operands
    powerOverflows :: RealFloat a => (Double -> a) -> Double -> Double -> Bool
    powerOverflows narrow x y = not (x == 0 && y < 0) && finite x && finite y && isInfinite (narrow (x ** y))
    asDouble = \case
      VInt _ k -> Just (fromInteger k)
      VReal y -> Just (float2Double y)
      VLReal y -> Just y
      _ -> Nothing

-- | MT-OP-7: did the unary minus overflow ('binaryOverflows')? A REAL's
-- never does; NOT and unary plus leave the flag.
unaryOverflows :: Policies -> UnOp -> Value -> Maybe Bool
unaryOverflows p op v = case (op, v) of
  (UNeg, VInt e x) -> Just (intOverflows p e (negate x))
  (UNeg, VReal _) -> Just False
  (UNeg, VLReal _) -> Just False
  _ -> Nothing

-- | Does an exact integer result leave the range 'intResult' fits it into?
intOverflows :: Policies -> Elem -> Integer -> Bool
intOverflows p e n
  | isBitString e = False
  | pArithWidth p == Promote32, isAnyInt e, intBits e < 32 = not (fitsUnder p DINT n)
  | otherwise = not (fitsUnder p e n)

-- | A fault that a checked program never meets: operands of types the
-- checker rejects.
illTyped :: Text -> Fault
illTyped what = Fault "internal" (what <> " is not defined (the checker should have rejected it)")

describe :: Value -> Text
describe v = maybe (renderValue v) elemName (valueElem v)
