-- | The memory model behind CODESYS's pointers (NX-TYPE-74..79,
-- docs/nexto.md): every variable has an address, a DWORD, and the bytes of
-- a variable lie as a C compiler lays them out.
--
-- * Sizes: BOOL, SINT, USINT, BYTE 1; INT, UINT, WORD and enumerations 2;
--   DINT, UDINT, DWORD, REAL, TIME, DATE, TOD, DT and pointers 4; LINT,
--   ULINT, LWORD, LREAL, LTIME 8; STRING(n) n + 1 bytes, WSTRING(n)
--   2(n + 1).
-- * Each scalar is aligned to its size, a string to its character, an array
--   to its element; a structure's and an instance's members follow one
--   another in declaration order, each at its alignment, and the whole is
--   rounded up to its largest alignment. A union's members all start at
--   its first byte; its size is its largest member's, rounded up likewise. Array elements are contiguous,
--   the last index varying fastest.
-- * The globals lie one after the other from 16#0001_0000, the program
--   instances from 16#4000_0000, the frame of a call at depth d at
--   16#8000_0000 + d * 16#0100_0000. Address 0 is the null pointer.
-- * Bytes are little-endian; REAL and LREAL are their IEEE 754 patterns,
--   TIME and TOD milliseconds, LTIME nanoseconds, DATE and DT seconds since
--   1970, an enumeration the position of its value, a string its
--   characters then NULs (the encoding a union's members share).
--
-- * Where no variable of a pointer's type starts at its address, the
--   pointer reads the bytes there as its type, each from the variable that
--   holds it ('leafAt'); a base type with an FB in it needs an instance
--   ('plainData').
--
-- Programs cannot depend on where a variable lies, only on distances inside
-- one variable (@ADR(a[2]) - ADR(a[1])@) and on pointer arithmetic in bytes.
module Stref.IEC.Memory
  ( Layout (..)
  , layout
  , remembering
  , sizeAlign
  , sizeInBytes
  , offsetOf
  , locate
  , leafAt
  , plainData
  , globalsBase
  , programsBase
  , frameBase
  , areaBase
  , areaAt
  , frameSpan
  , placeAll
  , encode
  , decode
  , unionMember
  , setUnionMember
  ) where

import Data.Bits (shiftL, shiftR, (.&.))
import Data.Char (chr, ord)
import Data.Foldable (toList)
import Data.List (dropWhileEnd, elemIndex, find)
import qualified Data.Map as ML
import qualified Data.Map.Strict as M
import Data.Maybe (fromMaybe, listToMaybe)
import qualified Data.Sequence as Seq
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word8)
import GHC.Float (castDoubleToWord64, castFloatToWord32, castWord32ToFloat, castWord64ToDouble)
import Stref.IEC.Types
import Stref.Policy (TimeRange (..))
import Stref.IEC.Values (Step (..), Value (..), defaultValue, wrapInt)

-- | What the layout needs to know of the unit: the members (upper-case
-- names and types) of a function block or program type, and the pack_mode
-- of a structure, union or POU type (NX-PRAGMA-11), by its upper-case name.
data Layout = Layout
  { lyMembers :: Text -> [(Text, Type)]
  , lyPack :: Text -> Maybe Integer
  , lyTimeRange :: TimeRange -- ^ how a TIME's four bytes count (policy time-range, NX-TYPE-30)
  , lyKnown :: Type -> Maybe Known
  -- ^ what 'remembering' computed beforehand for a named type; Nothing:
  -- computed by the rules
  }

-- | A type's size and alignment, and its members with their offsets, as
-- 'sizeAlign' and 'members' give them.
data Known = Known (Integer, Integer) (Maybe [(Text, Type, Integer)])

-- | A layout with the given members, pack modes and time range.
layout :: (Text -> [(Text, Type)]) -> (Text -> Maybe Integer) -> TimeRange -> Layout
layout ms pk tr = Layout ms pk tr (const Nothing)

-- | The same layout, which computes the size, alignment and members of
-- each named type among the given ones (and the types inside them) once,
-- when first asked, and then remembers them.
remembering :: [Type] -> Layout -> Layout
remembering ts ly = known
  where
    known = ly {lyKnown = \t -> named t >>= (`ML.lookup` table)}
    -- lazy: an entry is computed when first looked up
    table = ML.fromList [(k, Known (sizeAlignBy known t) (membersBy known t)) | t <- concatMap inside ts, Just k <- [named t]]
    inside t = t : case t of
      TArray _ et -> inside et
      TStruct _ fs -> concatMap (inside . snd) fs
      TUnion _ fs -> concatMap (inside . snd) fs
      _ -> []
    -- a named type by its name: one declaration gives a structure or
    -- union type its name (the checker's), a POU's layout follows from
    -- its name
    named :: Type -> Maybe (Int, Text)
    named = \case
      TStruct n _ | not (T.null n) -> Just (0, n)
      TUnion n _ | not (T.null n) -> Just (1, n)
      TFB n -> Just (2, n)
      TProgram n -> Just (3, n)
      _ -> Nothing

sizeAlign :: Layout -> Type -> (Integer, Integer)
sizeAlign ly t = maybe (sizeAlignBy ly t) (\(Known sa _) -> sa) (lyKnown ly t)

-- | The rules of the size and alignment of a type.
sizeAlignBy :: Layout -> Type -> (Integer, Integer)
sizeAlignBy ly = \case
  TElem e -> let n = elemSize e in (n, n)
  TString w n -> if w then (2 * (toInteger n + 1), 2) else (toInteger n + 1, 1)
  TArray bs t -> let (s, a) = sizeAlign ly t in (count bs * s, a)
  TStruct n fs -> packed (lyPack ly (upperName n)) (map snd fs)
  TEnum _ _ -> (2, 2)
  TNumEnum _ e _ -> let n = elemSize e in (n, n)
  TSubrange e _ _ -> let n = elemSize e in (n, n)
  TUnion n fs ->
    let sas = map (sizeAlign ly . snd) fs
        al = packAlign (lyPack ly (upperName n)) (maximum (1 : map snd sas))
     in (alignUp al (maximum (0 : map fst sas)), al)
  -- NX-PRAGMA-11: a POU may be packed too (L4562-4564)
  TFB n -> packed (lyPack ly (upperName n)) (map snd (lyMembers ly n))
  TProgram n -> packed (lyPack ly (upperName n)) (map snd (lyMembers ly n))
  TPointer _ -> (4, 4)
  TNamed _ -> (0, 1) -- never stored: only a pointer's target
  where
    packed pack ts =
      let (end, al) = foldl (\(off, a) t -> let ta = packAlign pack (snd (sizeAlign ly t)) in (alignUp ta off + fst (sizeAlign ly t), max a ta)) (0, 1) ts
       in (alignUp al end, al)

-- | A member's alignment under a structure's pack_mode (NX-PRAGMA-11): at
-- most the mode's bytes; 0 and 1 leave no gaps.
packAlign :: Maybe Integer -> Integer -> Integer
packAlign pack a = max 1 (maybe a (min a . max 1) pack)

sizeInBytes :: Layout -> Type -> Integer
sizeInBytes ly = fst . sizeAlign ly

elemSize :: Elem -> Integer
elemSize e
  | e == BOOL = 1
  | isInt e = toInteger (intBits e `div` 8)
  | e `elem` [LREAL, LTIME] = 8
  | otherwise = 4

alignUp :: Integer -> Integer -> Integer
alignUp a n = ((n + a - 1) `div` a) * a

count :: [(Integer, Integer)] -> Integer
count bs = product [hi - lo + 1 | (lo, hi) <- bs]

-- | The members of a structured type with their offsets.
members :: Layout -> Type -> Maybe [(Text, Type, Integer)]
members ly t = maybe (membersBy ly t) (\(Known _ ms) -> ms) (lyKnown ly t)

membersBy :: Layout -> Type -> Maybe [(Text, Type, Integer)]
membersBy ly t = case t of
  TUnion _ fs -> Just [(upperName k, ft, 0) | (k, ft) <- fs]
  _ -> members' ly t

members' :: Layout -> Type -> Maybe [(Text, Type, Integer)]
members' ly t = case t of
  TStruct n fs -> Just (place (lyPack ly (upperName n)) [(upperName k, ft) | (k, ft) <- fs])
  TFB n -> Just (place (lyPack ly (upperName n)) (lyMembers ly n))
  TProgram n -> Just (place (lyPack ly (upperName n)) (lyMembers ly n))
  _ -> Nothing
  where
    place pack fs = reverse (snd (foldl (step pack) (0, []) fs))
    step pack (off, acc) (k, ft) =
      let (s, a) = sizeAlign ly ft
          at = alignUp (packAlign pack a) off
       in (at + s, (k, ft, at) : acc)

-- | The offset of a path of steps inside a variable of a type, and the type
-- found there.
offsetOf :: Layout -> Type -> [Step] -> Maybe (Integer, Type)
offsetOf ly = go 0
  where
    go off t [] = Just (off, t)
    go off t (st : rest) = case (st, t) of
      (StepIndex is, TArray bs et) -> do
        lin <- linear bs is
        go (off + lin * sizeInBytes ly et) et rest
      (StepField k, _) -> do
        ms <- members ly t
        (_, ft, fo) <- find (\(n, _, _) -> n == k) ms
        go (off + fo) ft rest
      _ -> Nothing
    linear bs is
      | length bs /= length is = Nothing
      | and [i >= lo && i <= hi | ((lo, hi), i) <- zip bs is] =
          Just (foldl (\acc ((lo, hi), i) -> acc * (hi - lo + 1) + (i - lo)) 0 (zip bs is))
      | otherwise = Nothing

-- | The path to the variable of the wanted type at an offset inside a
-- variable of a type: Nothing when no variable of that type starts there.
-- A pointer to a function block may point at an instance of a derived one.
locate :: Layout -> Type -> Integer -> Type -> Maybe [Step]
locate ly t off want
  | off == 0 && fits t want = Just []
  | otherwise = case t of
      TArray bs et -> do
        let s = sizeInBytes ly et
            (i, r) = off `divMod` s
        if s <= 0 || off < 0 || i >= count bs
          then Nothing
          else (StepIndex (unlinear bs i) :) <$> locate ly et r want
      _ -> do
        ms <- members ly t
        -- in a union every member holds the offset: the first that has a
        -- variable of the type there
        listToMaybe [StepField k : found | (k, ft, fo) <- ms, off >= fo && off < fo + max 1 (sizeInBytes ly ft), Just found <- [locate ly ft (off - fo) want]]
  where
    fits a b = case (a, b) of
      (TFB _, TFB _) -> True
      (TString w1 _, TString w2 _) -> w1 == w2
      _ -> a == b || sameType a b

-- | The innermost variable holding the byte at an offset inside a
-- variable of a type: its path, its type and its first byte's offset.
-- Scalars, strings and unions are the leaves (a union holds bytes);
-- Nothing for a padding byte or an offset outside the type.
leafAt :: Layout -> Type -> Integer -> Maybe ([Step], Type, Integer)
leafAt ly t off
  | off < 0 || off >= sizeInBytes ly t = Nothing
  | otherwise = case t of
      TArray bs et -> do
        let s = sizeInBytes ly et
            (i, r) = off `divMod` s
        if s <= 0 || i >= count bs
          then Nothing
          else (\(steps, lt, at) -> (StepIndex (unlinear bs i) : steps, lt, i * s + at)) <$> leafAt ly et r
      TUnion {} -> Just ([], t, 0)
      _ -> case members ly t of
        Just ms ->
          listToMaybe [(StepField k : steps, lt, fo + at) | (k, ft, fo) <- ms, off >= fo, off < fo + sizeInBytes ly ft, Just (steps, lt, at) <- [leafAt ly ft (off - fo)]]
        Nothing -> Just ([], t, 0)

-- | Is a type data only, no function block or program in it: what the
-- bytes at an address can be read as when no variable of the type starts
-- there (NX-TYPE-75, docs/nexto.md).
plainData :: Type -> Bool
plainData = \case
  TArray _ et -> plainData et
  TStruct _ fs -> all (plainData . snd) fs
  TFB _ -> False
  TProgram _ -> False
  TNamed _ -> False
  _ -> True

-- | TC-TYPE-43: the indices of the i-th element, the last varying fastest.
unlinear :: [(Integer, Integer)] -> Integer -> [Integer]
unlinear bs i = snd (foldr (\(lo, hi) (rest, acc) -> let n = hi - lo + 1 in (rest `div` n, lo + rest `mod` n : acc)) (i, []) bs)

globalsBase, programsBase, frameSpan :: Integer
globalsBase = 0x00010000
programsBase = 0x40000000
frameSpan = 0x01000000

frameBase :: Int -> Integer
frameBase d = 0x80000000 + toInteger d * frameSpan

-- | The direct-address areas' bytes lie from 16#2000_0000 (%I), 16#2400_0000
-- (%Q) and 16#2800_0000 (%M), byte n of an area at its base + n, so that
-- ADR of a located variable is an address a pointer can follow.
areaBase :: Char -> Maybe Integer
areaBase = \case
  'I' -> Just 0x20000000
  'Q' -> Just 0x24000000
  'M' -> Just 0x28000000
  _ -> Nothing

-- | The area and byte an address of 'areaBase' names.
areaAt :: Integer -> Maybe (Char, Integer)
areaAt a = case [(c, a - b) | c <- "IQM", Just b <- [areaBase c], a >= b, a < b + 0x04000000] of
  found : _ -> Just found
  [] -> Nothing

-- | Variables laid out one after the other from a base: each with its
-- address.
placeAll :: Layout -> Integer -> [(a, Type)] -> [(a, Type, Integer)]
placeAll ly base = reverse . snd . foldl step (base, [])
  where
    step (off, acc) (x, t) =
      let (s, a) = sizeAlign ly t
          at = alignUp (max 1 a) off
       in (at + max 1 s, (x, t, at) : acc)

------------------------------------------------------------------------------
-- Bytes of a value (UNION: NX-TYPE-72, NX-TYPE-73)

-- | The bytes of a value of a type, as many as its size.
encode :: Layout -> Type -> Value -> [Word8]
encode ly t v = case (t, v) of
  (TElem BOOL, VBool b) -> [if b then 1 else 0]
  (TElem e, VInt _ n) | isInt e -> le (intBits e `div` 8) n
  (TElem REAL, VReal f) -> le 4 (toInteger (castFloatToWord32 f))
  (TElem LREAL, VLReal d) -> le 8 (toInteger (castDoubleToWord64 d))
  (TElem e, VTime _ n) -> le (if e == LTIME then 8 else 4) n
  (TElem _, VDate ms) -> le 4 (ms `div` 1000)
  (TElem _, VDT ms) -> le 4 (ms `div` 1000)
  (TElem _, VTod ms) -> le 4 ms
  (TString w n, VString s) ->
    let unit = if w then 2 else 1
     in take (unit * (n + 1)) (concatMap (le unit . toInteger . ord) (T.unpack s) ++ repeat 0)
  (TArray _ et, VArray _ xs) -> concatMap (encode ly et) (toList xs)
  (TStruct _ _, VStruct fs) -> record [(ft, fo, M.lookup k fs) | (k, ft, fo) <- fromMaybe [] (members ly t)]
  (TUnion _ _, VUnion _ bs) -> take size (bs ++ repeat 0)
  (TEnum _ vs, VEnum _ x) -> le 2 (maybe 0 toInteger (elemIndex x vs))
  (TNumEnum _ e _, VInt _ n) -> le (intBits e `div` 8) n
  (TSubrange e _ _, VInt _ n) -> le (intBits e `div` 8) n
  (TPointer _, VInt _ n) -> le 4 n
  _ -> replicate size 0
  where
    size = fromInteger (sizeInBytes ly t)
    le k n = [fromInteger ((n `shiftR` (8 * i)) .&. 255) | i <- [0 .. k - 1]]
    record parts = foldl (\bs (ft, fo, x) -> maybe bs (overlay bs (fromInteger fo) . encode ly ft) x) (replicate size 0) parts
    overlay bs at new = take at bs ++ new ++ drop (at + length new) bs

-- | The value of a type that bytes hold.
decode :: Layout -> Type -> [Word8] -> Value
decode ly t bs = case t of
  TElem BOOL -> VBool (any (/= 0) (take 1 bs))
  TElem e | isInt e -> VInt e (wrapInt e (num (intBits e `div` 8)))
  TElem REAL -> VReal (castWord32ToFloat (fromInteger (num 4)))
  TElem LREAL -> VLReal (castWord64ToDouble (fromInteger (num 8)))
  TElem LTIME -> VTime LTIME (signed 64 (num 8))
  TElem TIME -> VTime TIME (if lyTimeRange ly == TimeUnsigned then num 4 else wrapInt TIME (num 4))
  TElem DATE -> VDate (num 4 * 1000)
  TElem DT -> VDT (num 4 * 1000)
  TElem TOD -> VTod (num 4)
  TElem _ -> defaultValue t
  TString w _ ->
    let unit = if w then 2 else 1
        chars = [fromInteger (leNum (take unit (drop i bs))) | i <- [0, unit .. length bs - unit]]
     in VString (T.pack (map chr (takeWhile (/= 0) chars)))
  TArray b et ->
    let s = fromInteger (sizeInBytes ly et)
     in VArray b (Seq.fromList [decode ly et (take s (drop (i * s) bs)) | i <- [0 .. fromInteger (product [hi - lo + 1 | (lo, hi) <- b]) - 1]])
  TStruct _ _ -> VStruct (M.fromList [(k, decode ly ft (drop (fromInteger fo) bs)) | (k, ft, fo) <- fromMaybe [] (members ly t)])
  TUnion _ fs -> VUnion [(upperName k, ft) | (k, ft) <- fs] (dropWhileEnd (== 0) (take (fromInteger (sizeInBytes ly t)) bs))
  TEnum n vs -> let i = num 2 in if i < toInteger (length vs) then VEnum n (vs !! fromInteger i) else defaultValue t
  TNumEnum _ e _ -> VInt e (wrapInt e (num (intBits e `div` 8)))
  TSubrange e _ _ -> VInt e (wrapInt e (num (intBits e `div` 8)))
  TPointer _ -> VInt DWORD (num 4)
  _ -> defaultValue t
  where
    num k = leNum (take k (bs ++ repeat 0))
    leNum xs = sum [toInteger x `shiftL` (8 * i) | (i, x) <- zip [0 ..] xs]
    signed bits n = if n >= 2 ^ (bits - 1 :: Int) then n - 2 ^ bits else n

-- | NX-TYPE-72, NX-TYPE-73: a member of a union reads the bytes the
-- union holds.
unionMember :: Layout -> Text -> Value -> Maybe Value
unionMember ly k = \case
  VUnion fs bs -> (\t -> decode ly t bs) <$> lookup k fs
  _ -> Nothing

-- | Writing a member of a union replaces the bytes it covers; the bytes
-- beyond it keep what the union held.
setUnionMember :: Layout -> Text -> (Value -> Value) -> Value -> Value
setUnionMember ly k f = \case
  VUnion fs bs | Just t <- lookup k fs ->
    let new = encode ly t (f (decode ly t bs))
     in VUnion fs (dropWhileEnd (== 0) (new ++ drop (length new) bs))
  v -> v

