{-# LANGUAGE ForeignFunctionInterface #-}

-- | The standard functions of Tab.3.13-3.19 (Tecomat catalogue §4.2-4.6 and
-- §7.1; IEC 61131-3 ed.2 §2.5.1.5): their formal parameters, their typing
-- and their meaning under the policies. The operators' functions (ADD,
-- SUB, GT, AND, ...) are the operators of "Stref.IEC.Operators"; the
-- conversion functions are those of "Stref.IEC.Conversions", to which
-- 'standardType' and 'standard' hand every conversion name, so that a
-- checker may send every call that is not a user function here.
--
-- Generic arguments of one function have one type (TC-CONV-1), and the
-- result has that type (TC-CONV-2); the exceptions: the rows of Tab.3.20
-- (ADD(TOD, TIME), MUL(TIME, INT), ...), the exponent of EXPT, the N of
-- the shifts, and the ANY_INT positions and lengths of the string functions
-- (any integer type each, TC-CONV-5).
--
-- Under @standard-library = codesys@ also the functions of CODESYS's
-- util.library that the Nexto manual documents (BCD_TO_INT, INT_TO_BCD,
-- EXTRACT, PUTBIT, PACK: NX-FB-34..37) and TIME() (NX-OP-87): functions
-- with parameters of fixed types ('libraryFunction'), which the checker
-- binds as it binds a user function's.
module Stref.IEC.Standard
  ( standardNames
  , isStandardName
  , standardParameters
  , standardType
  , standard
  , libraryFunction
  , timeFunction
  , shiftNames
  ) where

import Control.Monad (foldM, unless, zipWithM, zipWithM_)
import Data.Bits (clearBit, setBit, shiftL, shiftR, testBit, (.&.), (.|.))
import Data.Text (Text)
import qualified Data.Text as T
import GHC.Float (double2Float, float2Double)
import Stref.IEC.Conversions (conversion, conversionType, isConversionName)
import Stref.IEC.Operators
import Stref.IEC.Syntax (BinOp (..), UnOp (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

-- | C's @log10@: exact at the powers of ten, which @logBase 10@ is not
-- (@logBase 10 1000 = 2.9999999999999996@).
foreign import ccall unsafe "math.h log10" c_log10 :: Double -> Double

-- | TC-OP-28: the functions of ANY_REAL. Decision: a REAL argument is
-- widened to binary64, the function computed there (by the C library, as
-- every 'Double' function of GHC) and the result rounded once to binary32.
realFunctions :: [(Text, Double -> Double)]
realFunctions =
  [ ("SQRT", sqrt)
  , ("LN", log)
  , ("LOG", c_log10)
  , ("EXP", exp)
  , ("SIN", sin)
  , ("COS", cos)
  , ("TAN", tan)
  , ("ASIN", asin)
  , ("ACOS", acos)
  , ("ATAN", atan)
  ]

-- | The operators' functions that take two or more inputs (TC-OP-19).
extensibleOps :: [(Text, BinOp)]
extensibleOps = [("ADD", BAdd), ("MUL", BMul), ("AND", BAnd), ("OR", BOr), ("XOR", BXor)]

-- | The operators' functions of exactly two inputs.
pairOps :: [(Text, BinOp)]
pairOps = [("SUB", BSub), ("DIV", BDiv), ("MOD", BMod), ("EXPT", BPow)]

-- | TC-OP-45: the comparison chains (NE is not extensible).
chainOps :: [(Text, BinOp)]
chainOps = [("GT", BGt), ("GE", BGe), ("EQ", BEq), ("LE", BLe), ("LT", BLt)]

shiftNames :: [Text]
shiftNames = ["SHL", "SHR", "ROR", "ROL"]

-- | Every standard function name, upper case (reserved for users: TC-LEX-3).
-- MUX is here (TC-OP-43, open: the manual does not list it; decision: it is
-- the IEC function).
standardNames :: [Text]
standardNames =
  ["ABS"] ++ map fst realFunctions ++ ["ADD", "MUL", "SUB", "DIV", "MOD", "EXPT", "MOVE"]
    ++ shiftNames ++ ["AND", "OR", "XOR", "NOT", "SEL", "MAX", "MIN", "LIMIT", "MUX"]
    ++ map fst chainOps ++ ["NE", "LEN", "LEFT", "RIGHT", "MID", "CONCAT", "INSERT", "DELETE", "REPLACE", "FIND"]

-- | A standard function's name (any case); not the conversions.
isStandardName :: Text -> Bool
isStandardName n = upperName n `elem` standardNames

-- | NX-OP-87, NX-TASK-9: @TIME()@, the time since the controller started,
-- is the virtual clock; the evaluator, which has it, computes the call.
timeFunction :: Text
timeFunction = "TIME"

-- | A function of fixed parameter types under @standard-library =
-- codesys@: its formal parameters (names and types, in order) and its
-- result type. util.library's, as the manual declares them (L13555-13660;
-- the parameter names of BCD_TO_INT and INT_TO_BCD, which the manual does
-- not print, are CODESYS's B and I), and TIME() (L8764-8776).
libraryFunction :: Policies -> Text -> Maybe ([(Text, Elem)], Elem)
libraryFunction p name
  | pStandardLibrary p == LibraryCodesys = lookup (upperName name) codesysLibrary
  | otherwise = Nothing

codesysLibrary :: [(Text, ([(Text, Elem)], Elem))]
codesysLibrary =
  [ ("BCD_TO_INT", ([("B", BYTE)], INT)) -- NX-CONV-39, NX-FB-34
  , ("INT_TO_BCD", ([("I", INT)], BYTE)) -- NX-CONV-40, NX-FB-34
  , ("EXTRACT", ([("X", DWORD), ("N", BYTE)], BOOL)) -- NX-FB-35
  , ("PUTBIT", ([("X", DWORD), ("N", BYTE), ("B", BOOL)], DWORD)) -- NX-FB-36
  , ("PACK", ([("B" <> T.pack (show i), BOOL) | i <- [0 .. 7 :: Int]], BYTE)) -- NX-FB-37
  , (timeFunction, ([], TIME)) -- NX-OP-87
  ]

-- | The formal parameter names of a call with @n@ arguments, in order (for
-- the extensible functions IN1..INn, for MUX K, IN0..INn-2); conversion
-- functions take IN. 'Nothing' for other names.
standardParameters :: Policies -> Text -> Int -> Maybe [Text]
standardParameters p name n = case upperName name of
  f
    | Just (params, _) <- libraryFunction p f -> Just (map fst params)
    | f `elem` (["ABS", "MOVE", "NOT", "LEN"] ++ map fst realFunctions) -> Just ["IN"]
    | f == "CONCAT", pStandardLibrary p == LibraryCodesys -> Just ["STR1", "STR2"] -- NX-STR-6
    | f `elem` (map fst extensibleOps ++ map fst chainOps ++ ["MAX", "MIN", "CONCAT"]) -> Just (numbered 1 (max 2 n))
    | f `elem` (map fst pairOps ++ ["NE", "FIND"]) -> Just ["IN1", "IN2"]
    | f `elem` shiftNames -> Just ["IN", "N"]
    | f `elem` ["LEFT", "RIGHT"] -> Just ["IN", "L"]
    | f `elem` ["MID", "DELETE"] -> Just ["IN", "L", "P"]
  "SEL" -> Just ["G", "IN0", "IN1"]
  "MUX" -> Just ("K" : numbered 0 (max 2 (n - 1)))
  "LIMIT" -> Just ["MN", "IN", "MX"]
  "INSERT" -> Just ["IN1", "IN2", "P"]
  "REPLACE" -> Just ["IN1", "IN2", "L", "P"]
  f | isConversionName p f -> Just ["IN"]
  _ -> Nothing
  where
    numbered from k = ["IN" <> T.pack (show i) | i <- take k [from :: Int ..]]

------------------------------------------------------------------------
-- Typing

-- | The result type of a call with arguments of these types: 'Nothing' when
-- the name is neither a standard function nor a conversion function, a
-- message when the arguments do not fit.
standardType :: Policies -> Text -> [Type] -> Maybe (Either Text Type)
standardType p name ts = case libraryFunction p f of
  Just (params, result) -> Just (libraryType params result)
  Nothing -> case typing p f ts of
    Nothing -> conversionType p f ts
    r -> r
  where
    f = upperName name
    libraryType params result
      | length ts /= length params = Left (f <> " takes " <> T.pack (show (length params)) <> " arguments, not " <> T.pack (show (length ts)))
      | and (zipWith (\t (_, e) -> baseElem t == Just e) ts params) = Right (TElem result)
      | otherwise = Left (f <> " takes " <> T.intercalate ", " [n <> " : " <> elemName e | (n, e) <- params])

typing :: Policies -> Text -> [Type] -> Maybe (Either Text Type)
typing p f ts = case f of
  "ABS" -> Just (one >>= generic isAnyNum "ANY_NUM") -- TC-OP-27
  _ | f `elem` map fst realFunctions -> Just (one >>= generic isAnyReal "ANY_REAL") -- TC-OP-28
  _ | Just op <- lookup f extensibleOps -> Just (atLeast 2 >> fold op) -- TC-OP-12, TC-OP-13, TC-OP-38
  _ | Just op <- lookup f pairOps -> Just (exactly 2 >> fold op) -- TC-OP-14..17
  "MOVE" -> Just one -- TC-OP-18
  _ | f `elem` shiftNames -> Just shiftType -- TC-OP-31..37
  "NOT" -> Just (one >>= either (Left . prefix) Right . unaryType UNot) -- TC-OP-38
  "SEL" -> Just selType -- TC-OP-40
  "MAX" -> Just (atLeast 2 >> allSame >>= ordered) -- TC-OP-41
  "MIN" -> Just (atLeast 2 >> allSame >>= ordered)
  "LIMIT" -> Just (exactly 3 >> allSame >>= ordered) -- TC-OP-42
  "MUX" -> Just muxType -- TC-OP-43
  _ | Just op <- lookup f chainOps -> Just (atLeast 2 >> chain op) -- TC-OP-45
  "NE" -> Just (exactly 2 >> chain BNe)
  "LEN" -> Just (exactly 1 >> str 1 >> Right (TElem INT)) -- TC-STR-3
  "LEFT" -> Just (exactly 2 >> int 2 >> firstString) -- TC-STR-4
  "RIGHT" -> Just (exactly 2 >> int 2 >> firstString) -- TC-STR-5
  "MID" -> Just (exactly 3 >> int 2 >> int 3 >> firstString) -- TC-STR-6
  "CONCAT" -> Just ((if pStandardLibrary p == LibraryCodesys then exactly 2 else atLeast 2) >> summed [1 .. length ts]) -- TC-STR-7; NX-STR-6: two inputs
  "INSERT" -> Just (exactly 3 >> int 3 >> summed [1, 2]) -- TC-STR-8
  "DELETE" -> Just (exactly 3 >> int 2 >> int 3 >> firstString) -- TC-STR-9
  "REPLACE" -> Just (exactly 4 >> int 3 >> int 4 >> summed [1, 2]) -- TC-STR-10
  "FIND" -> Just (exactly 2 >> summed [1, 2] >> Right (TElem INT)) -- TC-STR-11
  _ -> Nothing
  where
    prefix msg = f <> ": " <> msg
    count = length ts
    plural k = T.pack (show k) <> (if k == 1 then " argument" else " arguments")
    exactly k = unless (count == k) (Left (f <> " takes " <> plural k <> ", not " <> T.pack (show count)))
    atLeast k = unless (count >= k) (Left (f <> " takes at least " <> plural k <> ", not " <> T.pack (show count)))
    one = case ts of
      [t] -> Right t
      _ -> exactly 1 >> Left f
    arg i = ts !! (i - 1)
    generic test family t = case baseElem t of
      Just e | test e -> Right (TElem e)
      _ -> Left (f <> " takes " <> family <> ", not " <> typeText t)
    fold op = case ts of
      t : rest -> either (Left . prefix) Right (foldM (binaryType p op) t rest)
      [] -> Left f
    -- TC-CONV-1: all arguments of one type; strings of any capacities, the
    -- result holding the largest
    allSame = case ts of
      t : rest -> foldM common t rest
      [] -> Left f
    common a b = case (a, b) of
      (TString w n, TString w' m) | w == w' -> Right (TString w (max n m))
      _
        | sameType a b -> Right (plain a)
        | otherwise -> Left (f <> ": the arguments have different types, " <> typeText a <> " and " <> typeText b <> " " <> citing p ["TC-CONV-1", "NX-CONV-1", "NX-CONV-2"])
    plain t = maybe t TElem (baseElem t)
    ordered t = case binaryType p BLt t t of
      Right _ -> Right t
      Left _ -> Left (f <> " takes values with an order (numbers, bit strings, times, strings), not " <> typeText t)
    chain op = do
      _ <- allSame
      zipWithM_ (\a b -> either (Left . prefix) Right (binaryType p op a b)) ts (drop 1 ts)
      Right (TElem BOOL)
    shiftType = do
      exactly 2
      e <- case baseElem (arg 1) of
        -- TC-OP-37 (open): decision: BOOL is a bit string of width 1
        Just e | isAnyBit e -> Right e
        -- NX-OP-49: CODESYS also shifts the integers (SHR of a signed one is arithmetic)
        Just e | codesys, isAnyInt e, f `elem` ["SHL", "SHR"] -> Right e
        _ -> Left (f <> " shifts a bit string (ANY_BIT), not " <> typeText (arg 1))
      int 2
      Right (TElem e)
    selType = do
      exactly 3
      unless (baseElem (arg 1) == Just BOOL) (Left ("the selector G of SEL is a BOOL, not " <> typeText (arg 1)))
      common (arg 2) (arg 3)
    muxType = do
      atLeast 2
      int 1
      case drop 1 ts of
        t : rest -> foldM common t rest
        [] -> Left f
    -- TC-CONV-5: a position or length of any integer type (TC-OP-35: also
    -- the N of the shifts)
    codesys = pExtensions p == ExtensionsCodesys
    int i = case baseElem (arg i) of
      Just e | isAnyInt e -> Right ()
      -- NX-OP-66, NX-OP-54..57: CODESYS takes a count or selector of a bit string type too
      Just e | codesys, isBitString e -> Right ()
      _ -> Left (f <> ": argument " <> T.pack (show i) <> " is an integer (ANY_INT), not " <> typeText (arg i))
    str i = case arg i of
      TString w n -> Right (w, n)
      t -> Left (f <> ": argument " <> T.pack (show i) <> " is a STRING, not " <> typeText t)
    firstString = (\(w, n) -> TString w n) <$> str 1
    -- the result's capacity holds all the given strings (at most 65535);
    -- the strings are all STRING or all WSTRING
    summed is = do
      xs <- mapM str is
      case xs of
        (w, _) : _ | all ((== w) . fst) xs -> Right (TString w (min 65535 (sum (map snd xs))))
        _ -> Left (f <> " does not mix STRING and WSTRING")

------------------------------------------------------------------------
-- Meaning

-- | A standard (or conversion) function applied to arguments of the given
-- types, positional and complete.
standard :: Policies -> Text -> [Type] -> [Value] -> Either Fault Value
standard p name tys vs = case (f, vs) of
  _ | Just _ <- libraryFunction p f -> library f vs
  ("ABS", [v]) -> absValue p v
  (_, [v]) | Just fn <- lookup f realFunctions -> realFunction p fn v
  (_, v : rest@(_ : _)) | Just op <- lookup f extensibleOps -> foldM (binary p op) v rest
  (_, [a, b]) | Just op <- lookup f pairOps -> binary p op a b
  ("MOVE", [v]) -> Right v
  (_, [v, n]) | f `elem` shiftNames -> shiftValue f v n
  ("NOT", [v]) -> unary p UNot v
  ("SEL", [VBool g, a, b]) -> Right (if g then b else a) -- TC-OP-40
  ("MAX", v : rest@(_ : _)) -> foldM (pick BGt) v rest -- TC-OP-41
  ("MIN", v : rest@(_ : _)) -> foldM (pick BLt) v rest
  -- TC-OP-42, TC-OP-44: MIN(MAX(IN, MN), MX), so MX when MN > MX
  ("LIMIT", [mn, x, mx]) -> pick BGt x mn >>= \m -> pick BLt m mx
  ("MUX", k : ins@(_ : _)) -> intValue k >>= mux ins
  (_, _ : _ : _) | Just op <- lookup f chainOps -> VBool . and <$> zipWithM (test op) vs (drop 1 vs)
  ("NE", [a, b]) -> binary p BNe a b
  ("LEN", [VString s]) -> intResult p INT (toInteger (T.length s))
  ("LEFT", [VString s, l]) -> do
    n <- intValue l
    (i, k) <- window "LEFT" s 1 n
    result (T.take k (T.drop i s))
  ("RIGHT", [VString s, l]) -> do
    n <- intValue l
    (i, k) <- window "RIGHT" s (toInteger (T.length s) - n + 1) n
    result (T.take k (T.drop i s))
  ("MID", [VString s, l, pos]) -> do
    n <- intValue l
    q <- intValue pos
    (i, k) <- window "MID" s q n
    result (T.take k (T.drop i s))
  ("CONCAT", _ : _ : _) -> T.concat <$> mapM stringValue vs >>= result
  ("INSERT", [VString a, VString b, pos]) -> do
    q <- intValue pos
    -- TC-STR-13 (policy insert-position): IN2 starts at position P (at), or
    -- follows the P-th character (after, IEC)
    let start = case pInsertPosition p of
          InsertAt -> q
          InsertAfter -> q + 1
    (i, _) <- window "INSERT" a start 0
    result (T.take i a <> b <> T.drop i a)
  ("DELETE", [VString s, l, pos]) -> do
    n <- intValue l
    q <- intValue pos
    (i, k) <- window "DELETE" s q n
    result (T.take i s <> T.drop (i + k) s)
  ("REPLACE", [VString a, VString b, l, pos]) -> do
    n <- intValue l
    q <- intValue pos
    (i, k) <- window "REPLACE" a q n
    result (T.take i a <> b <> T.drop (i + k) a)
  ("FIND", [VString a, VString b]) -> intResult p INT (find a b)
  _
    | isConversionName p f -> conversion p f tys vs
    | otherwise -> Left (illTyped ("the function " <> f <> " of these arguments"))
  where
    f = upperName name
    pick op m x = do
      r <- binary p op x m
      Right (if r == VBool True then x else m)
    test op a b = (== VBool True) <$> binary p op a b
    mux ins k
      | k >= 0 && k < toInteger (length ins) = Right (ins !! fromInteger k)
      | otherwise = case pIndexOutOfRange p of
          IndexClamp -> Right (ins !! fromInteger (max 0 (min (toInteger (length ins) - 1) k)))
          _ -> Left (Fault "index-out-of-range" ("MUX selects input " <> T.pack (show k) <> " of " <> T.pack (show (length ins))))
    window = stringWindow p
    -- the capacity of the result type (TC-STR-18, policy string-overflow);
    -- reached only at 65535 characters or with arguments beyond their own
    -- capacities
    result s = case standardType p f tys of
      Just (Right (TString _ cap))
        | T.length s > cap -> case pStringOverflow p of
            StringTruncate -> Right (VString (T.take cap s))
            StringOverflowError -> Left (Fault "index-out-of-range" (f <> " gives " <> T.pack (show (T.length s)) <> " characters; its result holds " <> T.pack (show cap)))
      _ -> Right (VString s)

-- | The functions of 'libraryFunction' (not TIME(), which needs the clock).
library :: Text -> [Value] -> Either Fault Value
library f vs = case (f, vs) of
  ("BCD_TO_INT", [VInt _ b]) -> Right (VInt INT (bcdByte b))
  ("INT_TO_BCD", [VInt _ i]) -> Right (VInt BYTE (bcdOf i))
  ("EXTRACT", [VInt _ x, VInt _ n]) -> Right (VBool (extract x n))
  ("PUTBIT", [VInt _ x, VInt _ n, VBool b]) -> Right (VInt DWORD (putBit x n b))
  ("PACK", bs) | Just bits <- mapM bool bs -> Right (VInt BYTE (pack bits))
  _ -> Left (illTyped ("the function " <> f <> " of these arguments"))
  where
    bool = \case
      VBool b -> Just b
      _ -> Nothing

-- | NX-CONV-39: BCD_TO_INT, the two decimal digits of a BCD byte (tens in
-- bits 4-7, L13559-13564): 16#49 = 73 gives 49; a nibble above 9 is no
-- BCD byte and gives -1 (BCD_TO_INT(15) = -1).
bcdByte :: Integer -> Integer
bcdByte b =
  let (tens, ones) = b `divMod` 16
   in if tens > 9 || ones > 9 then -1 else tens * 10 + ones

-- | NX-CONV-40: INT_TO_BCD, 0..99 as a BCD byte (49 gives 16#49 = 73); any
-- other value, negative ones included, gives 255 (INT_TO_BCD(100) = 255).
bcdOf :: Integer -> Integer
bcdOf i
  | i >= 0 && i <= 99 = (i `div` 10) * 16 + i `mod` 10
  | otherwise = 255

-- | NX-FB-35: EXTRACT, bit N of the DWORD X, bits counted from 0
-- (EXTRACT(X := 81, N := 4) = TRUE). Decision: X has no bit 32 or above,
-- which reads FALSE.
extract :: Integer -> Integer -> Bool
extract x n = n < 32 && testBit x (fromInteger n)

-- | NX-FB-36: PUTBIT, X with bit N set to B (A = 38: PUTBIT(A, 4, TRUE) =
-- 54, PUTBIT(A, 1, FALSE) = 36). Decision: an N of 32 or above leaves X as
-- it is.
putBit :: Integer -> Integer -> Bool -> Integer
putBit x n b
  | n < 32 = (if b then setBit else clearBit) x (fromInteger n)
  | otherwise = x

-- | NX-FB-37: PACK, the BOOLs B0..B7 as the bits 0..7 of a BYTE.
pack :: [Bool] -> Integer
pack bits = sum [2 ^ i | (i, True) <- zip [0 :: Int ..] bits]

intValue :: Value -> Either Fault Integer
intValue = \case
  VInt _ n -> Right n
  v -> Left (illTyped ("an integer argument " <> renderValue v))

stringValue :: Value -> Either Fault Text
stringValue = \case
  VString s -> Right s
  v -> Left (illTyped ("a string argument " <> renderValue v))

-- | TC-OP-27, TC-OP-30 (open): ABS of the most negative integer overflows
-- and follows the @overflow@ policy (ABS(INT#-32768) is -32768 under
-- @wrap@, 32767 under @saturate@). Unsigned values are their own ABS; ABS
-- of a REAL clears the sign (also of -0.0 and NaN).
absValue :: Policies -> Value -> Either Fault Value
absValue p = \case
  VInt e x -> intResult p e (abs x)
  VReal x -> Right (VReal (abs x))
  VLReal x -> Right (VLReal (abs x))
  v -> Left (illTyped ("ABS of " <> renderValue v))

-- | TC-OP-28, TC-OP-29 (open): out of the domain the IEEE result (SQRT(-1.0)
-- and ASIN(2.0) are NaN, LN(0.0) is -inf); decision: an infinite result of
-- a finite argument (EXP(100.0) in REAL, LN(0.0)) follows @real-overflow@.
realFunction :: Policies -> (Double -> Double) -> Value -> Either Fault Value
realFunction p fn = \case
  VReal x -> Right (VReal (realOverflowFrom p (finite x) (double2Float (fn (float2Double x)))))
  VLReal x -> Right (VLReal (realOverflowFrom p (finite x) (fn x)))
  v -> Left (illTyped ("a REAL function of " <> renderValue v))

-- | SHL, SHR, ROL, ROR (TC-OP-31..34) of a bit string of width w (BOOL:
-- width 1, TC-OP-37). Shifts fill with zeros; N >= w gives 0. Rotations
-- rotate by N mod w. TC-OP-36 (open): decision: a negative N counts as 0
-- (the value is returned unchanged).
shiftValue :: Text -> Value -> Value -> Either Fault Value
shiftValue f v nv = do
  n <- intValue nv
  case v of
    VInt e x -> Right (VInt e (wrapInt e (bits (isSignedInt e) (intBits e) (x .&. mask (intBits e)) (max 0 n))))
    VBool b -> Right (VBool (bits False 1 (if b then 1 else 0) (max 0 n) /= 0))
    _ -> Left (illTyped (f <> " of " <> renderValue v))
  where
    mask w = 2 ^ w - 1 :: Integer
    bits :: Bool -> Int -> Integer -> Integer -> Integer
    bits signed w x n =
      let r = fromInteger (n `mod` toInteger w)
       in case f of
            "SHL" -> if n >= toInteger w then 0 else (x `shiftL` fromInteger n) .&. mask w
            "SHR"
              | signed -> let sx = if x >= 2 ^ (w - 1) then x - 2 ^ w else x in (sx `shiftR` fromInteger (min n (toInteger w))) .&. mask w -- NX-OP-49: the sign bit fills
              | n >= toInteger w -> 0
              | otherwise -> x `shiftR` fromInteger n
            "ROL" -> ((x `shiftL` r) .|. (x `shiftR` (w - r))) .&. mask w
            _ -> ((x `shiftR` r) .|. (x `shiftL` (w - r))) .&. mask w

-- | The characters from position @pos@ (1-based, TC-STR-1) on, @len@ of
-- them, of a string of n characters, as (characters before, count), under
-- @string-bounds@ (TC-STR-15..17, open):
--
-- * @clamp@: P below 1 counts as 1 and P beyond the end as n + 1 (the empty
--   rest), a negative L as 0, and L is cut to the characters there are;
-- * @error@: unless 1 <= P, 0 <= L and P + L - 1 <= n (the characters lie
--   in the string; with L = 0, P may be n + 1), a runtime error of kind
--   @index-out-of-range@.
--
-- LEFT(IN, L) is the window (1, L), RIGHT(IN, L) the window (n - L + 1, L),
-- INSERT's position the empty window there (1 <= P <= n + 1 under
-- insert-position=at, 0 <= P <= n under after).
stringWindow :: Policies -> Text -> Text -> Integer -> Integer -> Either Fault (Int, Int)
stringWindow p f s pos len = case pStringBounds p of
  StringClamp ->
    let start = max 1 (min (n + 1) pos)
        count = max 0 (min (n + 1 - start) len)
     in Right (fromInteger (start - 1), fromInteger count)
  StringBoundsError
    | pos >= 1 && len >= 0 && pos + len - 1 <= n -> Right (fromInteger (pos - 1), fromInteger len)
    | otherwise -> Left (Fault "index-out-of-range" (f <> ": " <> what <> " outside a string of " <> T.pack (show n) <> " characters"))
  where
    n = toInteger (T.length s)
    what
      | len == 0 = "position " <> T.pack (show pos) <> " is"
      | otherwise = T.pack (show len) <> " characters from position " <> T.pack (show pos) <> " are"

-- | FIND (TC-STR-11): the position of the first character of the first
-- occurrence of IN2 in IN1, case-sensitive; 0 if there is none. TC-STR-19
-- (open): decision: an empty IN2 is found at position 1 (as C's strstr
-- finds it at the start).
find :: Text -> Text -> Integer
find a b
  | T.null b = 1
  | otherwise =
      let (before, after) = T.breakOn b a
       in if T.null after then 0 else toInteger (T.length before) + 1
