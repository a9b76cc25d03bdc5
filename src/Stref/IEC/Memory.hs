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
--   rounded up to its largest alignment. Array elements are contiguous,
--   the last index varying fastest.
-- * The globals lie one after the other from 16#0001_0000, the program
--   instances from 16#4000_0000, the frame of a call at depth d at
--   16#8000_0000 + d * 16#0100_0000. Address 0 is the null pointer.
--
-- Programs cannot depend on where a variable lies, only on distances inside
-- one variable (@ADR(a[2]) - ADR(a[1])@) and on pointer arithmetic in bytes.
module Stref.IEC.Memory
  ( Layout (..)
  , sizeAlign
  , sizeInBytes
  , offsetOf
  , locate
  , globalsBase
  , programsBase
  , frameBase
  , frameSpan
  , placeAll
  ) where

import Data.List (find)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.IEC.Types
import Stref.IEC.Values (Step (..))

-- | What the layout needs to know of the unit: the members (upper-case
-- names and types) of a function block or program type.
newtype Layout = Layout {lyMembers :: Text -> [(Text, Type)]}

sizeAlign :: Layout -> Type -> (Integer, Integer)
sizeAlign ly = \case
  TElem e -> let n = elemSize e in (n, n)
  TString w n -> if w then (2 * (toInteger n + 1), 2) else (toInteger n + 1, 1)
  TArray bs t -> let (s, a) = sizeAlign ly t in (count bs * s, a)
  TStruct _ fs -> record (map snd fs)
  TEnum _ _ -> (2, 2)
  TNumEnum _ e _ -> let n = elemSize e in (n, n)
  TSubrange e _ _ -> let n = elemSize e in (n, n)
  TFB n -> record (map snd (lyMembers ly n))
  TProgram n -> record (map snd (lyMembers ly n))
  TPointer _ -> (4, 4)
  where
    record ts =
      let (end, al) = foldl (\(off, a) t -> let (s, ta) = sizeAlign ly t in (alignUp (max 1 ta) off + s, max a ta)) (0, 1) ts
       in (alignUp al end, al)

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
members ly t = place <$> case t of
  TStruct _ fs -> Just [(T.toUpper k, ft) | (k, ft) <- fs]
  TFB n -> Just (lyMembers ly n)
  TProgram n -> Just (lyMembers ly n)
  _ -> Nothing
  where
    place fs = reverse (snd (foldl step (0, []) fs))
    step (off, acc) (k, ft) =
      let (s, a) = sizeAlign ly ft
          at = alignUp (max 1 a) off
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
        (k, ft, fo) <- find (\(_, ft, fo) -> off >= fo && off < fo + max 1 (sizeInBytes ly ft)) ms
        (StepField k :) <$> locate ly ft (off - fo) want
  where
    fits a b = case (a, b) of
      (TFB _, TFB _) -> True
      (TString w1 _, TString w2 _) -> w1 == w2
      _ -> a == b || sameType a b
    unlinear bs i = snd (foldr (\(lo, hi) (rest, acc) -> let n = hi - lo + 1 in (rest `div` n, lo + rest `mod` n : acc)) (i, []) bs)

globalsBase, programsBase, frameSpan :: Integer
globalsBase = 0x00010000
programsBase = 0x40000000
frameSpan = 0x01000000

frameBase :: Int -> Integer
frameBase d = 0x80000000 + toInteger d * frameSpan

-- | Variables laid out one after the other from a base: each with its
-- address.
placeAll :: Layout -> Integer -> [(a, Type)] -> [(a, Type, Integer)]
placeAll ly base = reverse . snd . foldl step (base, [])
  where
    step (off, acc) (x, t) =
      let (s, a) = sizeAlign ly t
          at = alignUp (max 1 a) off
       in (at + max 1 s, (x, t, at) : acc)
