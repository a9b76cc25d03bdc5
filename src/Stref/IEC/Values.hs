-- | The values of the IEC types, exactly: integers of their widths, REAL as
-- binary32 and LREAL as binary64, times as counts of milliseconds, strings as
-- their characters (codes 0-255), arrays, structures, enumerated values and
-- function-block instances with their variables.
--
-- Also: default values (Tab.3.8, TC-TYPE-21/22) and the rendering of a value
-- as an ST literal (corpus-format §4.2).
module Stref.IEC.Values
  ( Value (..)
  , RefPath (..)
  , Root (..)
  , Step (..)
  , defaultValue
  , fitInt
  , wrapInt
  , renderValue
  , renderTime
  , renderDate
  , renderTod
  , renderDT
  , msPerDay
  , valueElem
  , Fault (..)
  ) where

import Data.Char (ord)
import Data.Map.Strict (Map)
import qualified Data.Map.Strict as M
import Data.Sequence (Seq)
import qualified Data.Sequence as Seq
import Data.Text (Text)
import Data.Word (Word8)
import qualified Data.Text as T
import Data.Time.Calendar (addDays, fromGregorian, toGregorian)
import Numeric (showFFloat, showHex)
import Stref.IEC.Types

data Value
  = VBool !Bool
  | VInt !Elem !Integer -- ^ an integer or bit-string type and a value within its range
  | VReal !Float
  | VLReal !Double
  | VTime !Elem !Integer -- ^ TIME or LTIME: milliseconds (TIME) or nanoseconds (LTIME)
  | VDate !Integer -- ^ milliseconds since 1970-01-01, at midnight
  | VTod !Integer -- ^ milliseconds since midnight
  | VDT !Integer -- ^ milliseconds since 1970-01-01
  | VString !Text -- ^ the characters; the capacity is the variable's type's
  | VEnum !Text !Text -- ^ the type's name and the value's name (as declared)
  | VArray ![(Integer, Integer)] !(Seq Value) -- ^ bounds and elements, row-major (TC-TYPE-43)
  | VStruct !(Map Text Value) -- ^ fields by upper-case name
  | VUnion ![(Text, Type)] ![Word8] -- ^ a UNION: its members (upper-case names, in order) and the bytes they share, without trailing zeros (Stref.IEC.Memory)
  | VInstance !Text !(Map Text Value) -- ^ an FB or program instance: its type and variables by upper-case name
  | VRef !RefPath -- ^ a VAR_IN_OUT parameter: where the caller's variable lies
  deriving (Eq, Show)

-- | Where a variable lies in the machine: a root and steps into it.
data RefPath = RefPath !Root ![Step]
  deriving (Eq, Ord, Show)

data Root
  = RootGlobal !Text -- ^ a global variable (upper-case name)
  | RootProgram !Text -- ^ a program instance
  | RootFrame !Int -- ^ the frame of a function call, by depth
  | RootLocated !Text -- ^ a direct address
  | RootBytes !Char !Integer !Type
  -- ^ CODESYS: what a pointer into a direct-address area reaches: the bytes
  -- of area I, Q or M from a byte address, read as a type (NX-TYPE-75)
  | RootAt !Integer !Type
  -- ^ CODESYS: what a pointer reaches where no variable of its type starts
  -- (an array of other bounds, a misaligned address): the bytes from an
  -- address, read as a type, taken from the variables that hold them
  -- (NX-TYPE-75, "Stref.IEC.Memory")
  deriving (Eq, Ord, Show)

data Step
  = StepField !Text
  | StepIndex ![Integer]
  | StepBit !Int -- ^ CODESYS: a bit of an integer, from 0 (NX-OP-92)
  | StepChar !Bool !Integer -- ^ a character of a STRING (False) or WSTRING (True), from 0, as its code
  deriving (Eq, Ord, Show)

-- | Tab.3.8: zeros, FALSE, T#0s, D#1970-01-01, TOD#00:00:00, the empty
-- string; the first value of an enumeration and the lower bound of a
-- subrange (TC-TYPE-21); arrays and structures element by element
-- (TC-TYPE-22). FB instances get their variables from the caller, who knows
-- the FB's declarations.
defaultValue :: Type -> Value
defaultValue = \case
  TElem e -> case e of
    BOOL -> VBool False
    REAL -> VReal 0
    LREAL -> VLReal 0
    TIME -> VTime TIME 0
    LTIME -> VTime LTIME 0
    DATE -> VDate 0
    TOD -> VTod 0
    DT -> VDT 0
    _ -> VInt e 0
  TString _ _ -> VString ""
  TArray bs t -> VArray bs (Seq.replicate (fromInteger (product [hi - lo + 1 | (lo, hi) <- bs])) (defaultValue t))
  TStruct _ fs -> VStruct (M.fromList [(T.toUpper n, defaultValue t) | (n, t) <- fs])
  TUnion _ fs -> VUnion [(T.toUpper n, t) | (n, t) <- fs] []
  TEnum n (v : _) -> VEnum n v
  TEnum n [] -> VEnum n ""
  TSubrange e lo _ -> VInt e lo
  TFB n -> VInstance n M.empty
  TProgram n -> VInstance n M.empty
  TPointer _ -> VInt DWORD 0 -- the null pointer
  TNamed _ -> VStruct M.empty -- never a variable's type: only a pointer's target
  TNumEnum _ e ((_, v) : _) -> VInt e v -- NX-TYPE-36: the first value
  TNumEnum _ e [] -> VInt e 0

-- | Is the integer within the type's range?
fitInt :: Elem -> Integer -> Bool
fitInt e n = let (lo, hi) = intRange e in n >= lo && n <= hi

-- | Two's complement wrap into the type's range (keeps the low bits): the
-- value of the range that differs from n by a multiple of 2^bits.
wrapInt :: Elem -> Integer -> Integer
wrapInt e n =
  let (lo, hi) = intRange e
   in lo + (n - lo) `mod` (hi - lo + 1)

valueElem :: Value -> Maybe Elem
valueElem = \case
  VBool _ -> Just BOOL
  VInt e _ -> Just e
  VReal _ -> Just REAL
  VLReal _ -> Just LREAL
  VTime e _ -> Just e
  VDate _ -> Just DATE
  VTod _ -> Just TOD
  VDT _ -> Just DT
  _ -> Nothing

-- | A runtime error of corpus-format §4.3: its kind (@division-by-zero@,
-- @index-out-of-range@, @subrange@, @overflow@, @conversion@, @watchdog@,
-- @call-depth@) and a message for the user. The evaluator adds the line.
data Fault = Fault {faultKind :: !Text, faultMessage :: !Text}
  deriving (Eq, Show)

msPerDay :: Integer
msPerDay = 86400000

-- | A value as an ST literal (corpus-format §4.2); numbers as JSON-like
-- decimals. Arrays and structures are shown as initialiser lists.
renderValue :: Value -> Text
renderValue = \case
  VBool b -> if b then "TRUE" else "FALSE"
  VInt _ n -> T.pack (show n)
  VReal f -> T.pack (show f)
  VLReal d -> T.pack (show d)
  VTime e n -> renderTime e n
  VDate ms -> renderDate ms
  VTod ms -> renderTod ms
  VDT ms -> renderDT ms
  VString s -> "'" <> T.concatMap escape s <> "'"
  VEnum t v -> if T.null t then v else t <> "#" <> v
  VArray _ xs -> "[" <> T.intercalate ", " (map renderValue (foldr (:) [] xs)) <> "]"
  VStruct fs -> "(" <> T.intercalate ", " [k <> " := " <> renderValue v | (k, v) <- M.toList fs] <> ")"
  VUnion _ bs -> "UNION#16#" <> T.pack (concatMap (\b -> (if b < 16 then "0" else "") <> showHex b "") bs)
  VInstance t _ -> "<instance of " <> t <> ">"
  VRef _ -> "<reference>"
  where
    escape c
      | c == '\'' = "$'"
      | c == '$' = "$$"
      | ord c < 32 || ord c > 126 = "$" <> hex2 (ord c)
      | otherwise = T.singleton c
    hex2 n = let h = showHex n "" in T.toUpper (T.pack (replicate (2 - length h) '0' ++ h))

-- | @T#1d2h3m4s5ms@ (TIME: milliseconds; LTIME: nanoseconds).
renderTime :: Elem -> Integer -> Text
renderTime e n0 =
  prefix <> sign <> if T.null body then "0ms" else body
  where
    prefix = if e == LTIME then "LTIME#" else "T#"
    sign = if n0 < 0 then "-" else ""
    ns = abs n0 * (if e == LTIME then 1 else 1000000)
    units = [("d", 86400 * 10 ^ (9 :: Int)), ("h", 3600 * 10 ^ (9 :: Int)), ("m", 60 * 10 ^ (9 :: Int)), ("s", 10 ^ (9 :: Int)), ("ms", 10 ^ (6 :: Int)), ("us", 1000), ("ns", 1)]
    body = T.concat (go ns units)
    go _ [] = []
    go r ((u, size) : rest) =
      let (q, r') = r `divMod` size
       in (if q > 0 then [T.pack (show q) <> u] else []) ++ go r' rest

renderDate :: Integer -> Text
renderDate ms = "D#" <> dayText (ms `div` msPerDay)

renderTod :: Integer -> Text
renderTod ms = "TOD#" <> clockText ms

renderDT :: Integer -> Text
renderDT ms = "DT#" <> dayText (ms `div` msPerDay) <> "-" <> clockText (ms `mod` msPerDay)

dayText :: Integer -> Text
dayText d =
  let (y, m, dd) = toGregorian (addDays d (fromGregorian 1970 1 1))
   in T.pack (show y) <> "-" <> two (toInteger m) <> "-" <> two (toInteger dd)

clockText :: Integer -> Text
clockText ms =
  let (h, r1) = ms `divMod` 3600000
      (m, r2) = r1 `divMod` 60000
      (s, f) = r2 `divMod` 1000
   in two h <> ":" <> two m <> ":" <> two s <> (if f == 0 then "" else T.dropWhileEnd (== '0') (T.pack (drop 1 (showFFloat (Just 3) (fromInteger f / 1000 :: Double) ""))))

two :: Integer -> Text
two n = if n < 10 then "0" <> T.pack (show n) else T.pack (show n)
