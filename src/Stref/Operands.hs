{-# OPTIONS_GHC -O2 #-}
-- (the interpreter's hot path: bench/RESULTS.md measures -O2 against -O1)
{-# LANGUAGE MagicHash #-}
-- | PLC operands (catalogue §7.3, Tables 2-3 and 4-8): which operands the
-- language knows, which types may be mapped onto them, the controller's
-- configuration (which operands are declared) and its memory.
module Stref.Operands
  ( SimpleKind (..)
  , TableKind (..)
  , Operand (..)
  , Cell (..)
  , resolveOperand
  , OperandProblem (..)
  , describeOperandProblem
  , parseOperand
  , renderOperand
  , operandCell
  , compatibleType
  , operandKindCode
  , simpleLetter
  , tableLetters
  -- * CHF parameters
  , ConstKind (..)
  , ChfArg (..)
  , parseChfArg
  -- * The controller's configuration
  , PlcConfig (..)
  , defaultPlcConfig
  , cellDeclared
  -- * Memory
  , Memory
  , emptyMemory
  , readCell
  , lookupCell
  , writeCell
  , readOperand
  , writeOperand
  , operandReader
  , operandWriter
  , cellWidth
  , cellCells
  -- * Cells held apart during a module call
  , CellSlots
  , cellSlots
  , CellKey
  , cellKey
  , lookupSlot
  , heldPattern
  , cellMask
  , takeCells
  , putCells
  ) where

import Data.Bits (clearBit, setBit, shiftL, shiftR, testBit, (.&.), (.|.))
import Data.Char (isDigit, isSpace, toUpper)
import Control.Monad (forM)
import Control.Monad.ST (runST)
import qualified Data.IntSet as IS
import GHC.Exts (isTrue#, reallyUnsafePtrEquality#)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Vector as V
import qualified Data.Vector.Mutable as MV
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU
import Data.Word (Word32, Word64)
import Stref.Syntax (OperandRef (..), OperandSub (..))
import Stref.Types
import Stref.Values

-- | Simple operands: %E, %S, %A are octets, %M 16-bit memories, %I 32-bit
-- integers, %F binary32 reals (Table 2-1, MT-MAP-17).
data SimpleKind = KE | KS | KA | KM | KI | KF
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Table operands: %TM (16-bit), %TI (32-bit), %TF (real).
data TableKind = TM | TI | TF
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | An operand that ST may map a variable onto (MT-MAP-2, MT-MAP-5, MT-MAP-6).
data Operand
  = OpSimple SimpleKind Int -- ^ @%M0010@
  | OpBit SimpleKind Int Int -- ^ @%M0006.6@: %E, %S, %A (bits 0..7), %M (0..15)
  | OpTablePos TableKind Int Int -- ^ @%TM010[15]@
  deriving (Eq, Ord, Show)

-- | A unit of controller memory: one simple operand or one table position.
data Cell
  = CellSimple SimpleKind Int
  | CellTable TableKind Int Int
  deriving (Eq, Show)

-- | The order a derived instance would give (simple cells first, then by
-- kind, address, position), written out so that it inlines into the
-- memory's map operations: every operand access compares cells.
instance Ord Cell where
  compare (CellSimple k a) (CellSimple k' a') = compare (fromEnum k) (fromEnum k') <> compare a a'
  compare (CellSimple {}) (CellTable {}) = LT
  compare (CellTable {}) (CellSimple {}) = GT
  compare (CellTable k a p) (CellTable k' a' p') = compare (fromEnum k) (fromEnum k') <> compare a a' <> compare p p'
  {-# INLINE compare #-}

simpleLetter :: SimpleKind -> Text
simpleLetter = \case
  KE -> "E"
  KS -> "S"
  KA -> "A"
  KM -> "M"
  KI -> "I"
  KF -> "F"

tableLetters :: TableKind -> Text
tableLetters = \case
  TM -> "TM"
  TI -> "TI"
  TF -> "TF"

data OperandProblem
  = UnknownOperandKind Text -- ^ %D, %TD, %X ... (MT-MAP-2: not usable from ST)
  | BitNotAllowed Text -- ^ a bit of %I, %F or a table
  | BitOutOfRange Text Integer Int -- ^ @%M0001.16@: letters, bit, width
  | TablePositionRequired Text -- ^ @%TM0010@ without @[n]@ after AT (MT-MAP-9)
  | PositionNotAllowed Text -- ^ @%M0010[3]@
  | AddressTooLarge Text Integer
  deriving (Eq, Show)

describeOperandProblem :: OperandProblem -> Text
describeOperandProblem = \case
  UnknownOperandKind l -> "%" <> l <> " is not an operand ST can use (only %E, %S, %A, %M, %I, %F, %TM, %TI, %TF)"
  BitNotAllowed l -> "a bit of %" <> l <> " cannot be mapped (bits exist only in %E, %S, %A and %M)"
  BitOutOfRange l b w -> "bit " <> tshow b <> " does not exist in %" <> l <> " (bits 0.." <> tshow (w - 1) <> ")"
  TablePositionRequired l -> "%" <> l <> " needs the table position, e.g. %" <> l <> "0010[0]"
  PositionNotAllowed l -> "%" <> l <> " is not a table; it takes no [position]"
  AddressTooLarge l a -> "address " <> tshow a <> " of %" <> l <> " is too large"
  where
    tshow :: Show x => x -> Text
    tshow = T.pack . show

-- | Validate an address as written (MT-MAP-2, MT-MAP-6; MT-VERR-39).
resolveOperand :: OperandRef -> Either OperandProblem Operand
resolveOperand (OperandRef letters addr sub)
  | addr > 65535 = Left (AddressTooLarge letters addr)
  | Just k <- lookup letters simpleKinds = case sub of
      NoSub -> Right (OpSimple k a)
      BitOf b
        | k `elem` [KI, KF] -> Left (BitNotAllowed letters)
        | b < 0 || b >= fromIntegral (bitWidth k) -> Left (BitOutOfRange letters b (bitWidth k))
        | otherwise -> Right (OpBit k a (fromInteger b))
      Position _ -> Left (PositionNotAllowed letters)
  | Just k <- lookup letters tableKinds = case sub of
      Position p | p <= 65535 -> Right (OpTablePos k a (fromInteger p))
      Position p -> Left (AddressTooLarge letters p)
      BitOf _ -> Left (BitNotAllowed letters)
      NoSub -> Left (TablePositionRequired letters)
  | otherwise = Left (UnknownOperandKind letters)
  where
    a = fromInteger addr
    simpleKinds = [(simpleLetter k, k) | k <- [minBound .. maxBound]]
    tableKinds = [(tableLetters k, k) | k <- [minBound .. maxBound]]
    bitWidth k = if k == KM then 16 else 8 :: Int

-- | Read an operand from its text, as the corpus and the CLI write it:
-- @%M0010@, @%M10@, @%M0013.0@, @%TM0010[5]@, @%F0002@.
parseOperand :: Text -> Either Text Operand
parseOperand t0 = do
  let t = T.filter (not . isSpace) t0
  rest <- maybe (Left ("operand '" <> t0 <> "' must start with %")) Right (T.stripPrefix "%" t)
  let (letters, r1) = T.span (`elem` ['A' .. 'Z']) (T.map toUpper rest)
      (digits, r2) = T.span isDigit r1
  if T.null letters || T.null digits
    then Left ("'" <> t0 <> "' is not an operand address")
    else do
      sub <- case T.unpack r2 of
        "" -> Right NoSub
        '.' : ds | not (null ds), all isDigit ds -> Right (BitOf (read ds))
        '[' : ds | not (null ds), last ds == ']', all isDigit (init ds), not (null (init ds)) -> Right (Position (read (init ds)))
        _ -> Left ("'" <> t0 <> "' is not an operand address")
      either (Left . describeOperandProblem) Right
        (resolveOperand (OperandRef letters (read (T.unpack digits)) sub))

-- | The canonical spelling: four-digit addresses, as the manual writes them.
renderOperand :: Operand -> Text
renderOperand = \case
  OpSimple k a -> "%" <> simpleLetter k <> pad a
  OpBit k a b -> "%" <> simpleLetter k <> pad a <> "." <> T.pack (show b)
  OpTablePos k a p -> "%" <> tableLetters k <> pad a <> "[" <> T.pack (show p) <> "]"
  where
    pad n = let s = show n in T.pack (replicate (4 - length s) '0' ++ s)

operandCell :: Operand -> Cell
operandCell = \case
  OpSimple k a -> CellSimple k a
  OpBit k a _ -> CellSimple k a
  OpTablePos k a p -> CellTable k a p

-- | Table 4-8 (MT-MAP-5): the types a variable mapped onto the operand may have.
compatibleType :: Operand -> BasicType -> Bool
compatibleType op t = case op of
  OpBit {} -> t == BOOL
  OpSimple k _ -> t `elem` simpleTypes k
  OpTablePos k _ _ -> t `elem` tableTypes k
  where
    simpleTypes = \case
      KE -> [USINT, BYTE]
      KS -> [USINT, BYTE]
      KA -> [USINT, BYTE]
      KM -> [INT, WORD]
      KI -> [DINT, DWORD]
      KF -> [REAL]
    tableTypes = \case
      TM -> [INT, WORD]
      TI -> [DINT, DWORD]
      TF -> [REAL]

-- | Comp 1 of runtime errors 2000-2002 (Table 5-3): 0 %M, 8 %E/%S, 9 %A,
-- 4 %F, 1 %I; tables use the code of their element kind.
operandKindCode :: Cell -> Int
operandKindCode = \case
  CellSimple k _ -> case k of
    KM -> 0
    KE -> 8
    KS -> 8
    KA -> 9
    KF -> 4
    KI -> 1
  CellTable k _ _ -> case k of
    TM -> 0
    TF -> 4
    TI -> 1

-- | Constant operands, usable only as CHF input parameters (MT-PARAM-7).
data ConstKind = KMConst | KIConst | KFConst
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | An argument of the CHF instruction that calls an F module (MT-PARAM-3..7):
-- an operand (for an array: the first of a block of simple operands, or a
-- table position), a whole table, or a constant @%KM+5@, @%KI-7@, @%KF+2.5@.
data ChfArg
  = ChfOperand Operand
  | ChfTable TableKind Int
  | ChfConstant ConstKind Rational
  deriving (Eq, Show)

-- | Read a CHF argument as the corpus writes it.
parseChfArg :: Text -> Either Text ChfArg
parseChfArg t0 = case T.unpack (T.toUpper (T.filter (not . isSpace) t0)) of
  '%' : 'K' : k : rest
    | Just kind <- lookup k [('M', KMConst), ('I', KIConst), ('F', KFConst)] ->
        maybe (Left ("'" <> t0 <> "' is not a constant operand (e.g. %KM+5, %KF-2.5)")) (Right . ChfConstant kind) (signedNumber rest)
  '%' : 'T' : k : ds
    | Just kind <- lookup k [('M', TM), ('I', TI), ('F', TF)], not (null ds), all isDigit ds ->
        Right (ChfTable kind (read ds))
  _ -> ChfOperand <$> parseOperand t0
  where
    signedNumber s = case s of
      '+' : r -> number r
      '-' : r -> negate <$> number r
      _ -> Nothing
    number r = case break (== '.') r of
      (i, "") | not (null i), all isDigit i -> Just (fromInteger (read i))
      (i, '.' : f) | not (null i), not (null f), all isDigit (i ++ f) ->
        Just (fromInteger (read (i ++ f)) / (10 ^ length f))
      _ -> Nothing

-- | The configuration module: how many of each simple operand exist, which
-- tables exist with how many positions, and where the five diagnostic
-- operands start (MT-EXEC-1, MT-DIAG-2).
data PlcConfig = PlcConfig
  { plcSimple :: M.Map SimpleKind Int
  , plcTables :: M.Map (TableKind, Int) Int
  , plcDiagnostics :: Int -- ^ the first %M of the diagnostic band
  }
  deriving (Eq, Show)

-- | The project's default layout (documented in conformance/README.md):
-- %M0000..%M1999, %E and %S 0..15, %A 0..63, %I and %F 0..99, tables
-- %TM0010 (200 positions), %TM0030 (100), %TI0010 (50), %TF0010 (50), and the
-- diagnostic band at %M1990..%M1994.
defaultPlcConfig :: PlcConfig
defaultPlcConfig =
  PlcConfig
    { plcSimple = M.fromList [(KM, 2000), (KE, 16), (KS, 16), (KA, 64), (KI, 100), (KF, 100)]
    , plcTables = M.fromList [((TM, 10), 200), ((TM, 30), 100), ((TI, 10), 50), ((TF, 10), 50)]
    , plcDiagnostics = 1990
    }

cellDeclared :: PlcConfig -> Cell -> Bool
cellDeclared cfg = \case
  CellSimple k a -> a >= 0 && a < M.findWithDefault 0 k (plcSimple cfg)
  CellTable k a p -> maybe False (\n -> p >= 0 && p < n) (M.lookup (k, a) (plcTables cfg))

-- | Every cell of a configuration (for reports of the whole memory).
cellCells :: PlcConfig -> [Cell]
cellCells cfg =
  [CellSimple k a | (k, n) <- M.toList (plcSimple cfg), a <- [0 .. n - 1]]
    ++ [CellTable k a p | ((k, a), n) <- M.toList (plcTables cfg), p <- [0 .. n - 1]]

-- | Width of a cell in bits.
cellWidth :: Cell -> Int
cellWidth = \case
  CellSimple k _ -> case k of
    KM -> 16
    KI -> 32
    KF -> 32
    _ -> 8
  CellTable k _ _ -> if k == TM then 16 else 32

-- | Controller memory: each cell holds the bit pattern of its width; a cell
-- never written reads as 0 (every declared operand starts at 0).
--
-- A module's mapped cells may be held apart, in an unboxed vector laid out
-- by a 'CellSlots' table ('takeCells', 'putCells'): a module call then
-- takes them from the memory and puts them back without a map operation.
-- The two parts never hold the same cell; equality and 'show' are those of
-- the whole memory as one map, whichever part holds a cell.
data Memory = Memory !(M.Map Cell Word32) !HeldCells

data HeldCells
  = NoHeldCells
  | HeldCells !CellSlots !(U.Vector Int) -- ^ each slot's pattern, bit 32 set when the cell holds one

instance Eq Memory where
  a == b = memoryMap a == memoryMap b

instance Show Memory where
  showsPrec d mem = showParen (d > 10) (showString "Memory " . showsPrec 11 (memoryMap mem))

-- | The whole memory as one map.
memoryMap :: Memory -> M.Map Cell Word32
memoryMap (Memory m held) = case held of
  NoHeldCells -> m
  HeldCells ct vals ->
    M.union m $
      M.fromList
        [ (V.unsafeIndex (ctCells ct) j, fromIntegral v)
        | j <- U.toList (ctUsed ct)
        , let v = U.unsafeIndex vals j
        , testBit v 32
        ]

emptyMemory :: Memory
emptyMemory = Memory M.empty NoHeldCells

readCell :: Memory -> Cell -> Word32
readCell mem c = maybe 0 id (lookupCell mem c)

-- | The pattern of a cell that has been written, if it has.
lookupCell :: Memory -> Cell -> Maybe Word32
lookupCell (Memory m held) c = case held of
  HeldCells ct vals
    | j >= 0 ->
        let v = U.unsafeIndex vals j
         in if testBit v 32 then Just (fromIntegral v) else Nothing
    where
      j = lookupSlot ct (cellKey c)
  _ -> M.lookup c m

writeCell :: Cell -> Word32 -> Memory -> Memory
writeCell c w (Memory m held) = case held of
  HeldCells ct vals
    | j >= 0 -> Memory m (HeldCells ct (vals U.// [(j, heldPattern (w .&. cellMask c))]))
    where
      j = lookupSlot ct (cellKey c)
  _ -> Memory (M.insert c (w .&. cellMask c) m) held

-- | The bits of a cell's pattern: its width's low bits.
cellMask :: Cell -> Word32
cellMask c = if width >= 32 then maxBound else (1 `shiftL` width) - 1
  where
    width = cellWidth c

-- | A pattern as a held slot holds it: bit 32 says the cell holds one.
heldPattern :: Word32 -> Int
heldPattern w = (1 `shiftL` 32) .|. fromIntegral w
{-# INLINE heldPattern #-}

-- | The cells of a table taken apart from a memory: the memory without
-- them, and their patterns slot by slot ('heldPattern', 0 for a cell never
-- written). Cheap when the memory already holds them apart in that table
-- (the memory a call with the same table left).
takeCells :: CellSlots -> Memory -> (Memory, U.Vector Int)
takeCells ct mem@(Memory m held) = case held of
  HeldCells ct' vals | sameTable ct' ct -> (Memory m NoHeldCells, vals)
  _ ->
    let whole = memoryMap mem
        cells = [(j, V.unsafeIndex (ctCells ct) j) | j <- U.toList (ctUsed ct)]
        vals = U.replicate (ctMask ct + 1) 0 U.// [(j, heldPattern w) | (j, c) <- cells, Just w <- [M.lookup c whole]]
     in (Memory (foldr (M.delete . snd) whole cells) NoHeldCells, vals)

-- | Whether two tables place the same cells in the same slots: at once when
-- they are one table (every call of a module uses one), else by their keys.
sameTable :: CellSlots -> CellSlots -> Bool
sameTable a b = isTrue# (reallyUnsafePtrEquality# a b) || ctKeys a == ctKeys b

-- | The inverse of 'takeCells': the memory with the table's cells holding
-- the given patterns (the memory must not hold them itself).
putCells :: CellSlots -> U.Vector Int -> Memory -> Memory
putCells ct vals (Memory m _) = Memory m (HeldCells ct vals)

-- | Which slot of a small vector holds which cell: an open-addressing table
-- built once per module, so that finding a cell at run time is a probe or
-- two in unboxed memory (the cell's key and hash computed beforehand).
data CellSlots = CellSlots
  { ctMask :: !Int -- ^ the number of slots (a power of two) minus one
  , ctKeys :: !(U.Vector Int) -- ^ each slot's cell key, 'noKey' when empty
  , ctCells :: !(V.Vector Cell) -- ^ each slot's cell (any cell when empty)
  , ctUsed :: !(U.Vector Int) -- ^ the slots in use
  }

-- | A cell as a number (different cells, different numbers), with its hash;
-- 'noKey' for a cell whose address or position is too large to encode (it
-- is never in a table).
data CellKey = CellKey !Int !Int

noKey :: Int
noKey = -1

cellKey :: Cell -> CellKey
cellKey c = CellKey key (hash key)
  where
    key = case c of
      CellSimple k a -> encode 0 (fromEnum k) a 0
      CellTable k a p -> encode 1 (fromEnum k) a p
    -- tag: bit 62, kind: bits 56..58, address: 28..55, position: 0..27
    encode :: Int -> Int -> Int -> Int -> Int
    encode tag kind a p
      | a < 0 || a >= limit || p < 0 || p >= limit = noKey
      | otherwise = (tag `shiftL` 62) .|. (kind `shiftL` 56) .|. (a `shiftL` 28) .|. p
    limit = 1 `shiftL` 28
    -- Fibonacci hashing; the table's mask takes the low bits
    hash k = fromIntegral ((fromIntegral k * 0x9E3779B97F4A7C15 :: Word64) `shiftR` 32)

-- | The table of the given cells (duplicates once), at most half full;
-- each cell at the first free slot from its hash, in the order given.
cellSlots :: [Cell] -> CellSlots
cellSlots cells0 = runST $ do
  keysM <- MU.replicate size noKey
  cellsM <- MV.replicate size (CellSimple KM 0)
  let -- a free slot exists: the table is at most half full
      free j = MU.read keysM j >>= \k -> if k == noKey then pure j else free ((j + 1) .&. mask)
  used <- forM cells $ \c -> do
    let CellKey k h = cellKey c
    j <- free (h .&. mask)
    MU.write keysM j k
    MV.write cellsM j c
    pure j
  CellSlots mask <$> U.freeze keysM <*> V.freeze cellsM <*> pure (U.fromList used)
  where
    -- the first of equal cells (equal keys); not 'nubOrd' on cells, whose
    -- specialisation here made GHC 9.0.2 build a program that crashes
    -- (segmentation fault in `stref engine`)
    cells = go IS.empty cells0
      where
        go _ [] = []
        go seen (c : rest)
          | k == noKey || k `IS.member` seen = go seen rest
          | otherwise = c : go (IS.insert k seen) rest
          where
            CellKey k _ = cellKey c
    size = until (>= 2 * length cells) (* 2) 1
    mask = size - 1

-- | The slot of a cell, or -1 when the table does not hold it.
lookupSlot :: CellSlots -> CellKey -> Int
lookupSlot ct (CellKey key h)
  | key == noKey = -1
  | otherwise = go (h .&. mask)
  where
    mask = ctMask ct
    keys = ctKeys ct
    go j =
      let k = U.unsafeIndex keys j
       in if k == key then j else if k == noKey then -1 else go ((j + 1) .&. mask)
{-# INLINE lookupSlot #-}

-- | The value of an integer type held by a cell's pattern: its low bits
-- ('integerToValue' of the pattern, without an 'Integer').
wordToValue :: BasicType -> Word32 -> Value
wordToValue t w = intToValue t (fromIntegral w)

-- | The pattern of an integer value: its low 32 bits (two's complement for
-- a negative number, as 'valueToInteger' modulo 2^32); REAL is written by
-- its bits, never through this.
valueToWord :: Value -> Word32
valueToWord = maybe 0 fromIntegral . valueToInt

-- | Read a variable of the given type mapped onto the operand.
readOperand :: Memory -> Operand -> BasicType -> Value
readOperand mem op t = operandReader op t (readCell mem (operandCell op))

-- | Write a value through an operand: a bit changes only its bit.
writeOperand :: Operand -> Value -> Memory -> Memory
writeOperand op v mem = case op of
  OpBit {} -> writeCell c (operandWriter op v (readCell mem c)) mem
  _ -> writeCell c (operandWriter op v 0) mem -- the old pattern is not used
  where
    c = operandCell op

-- | 'readOperand' on the pattern of the operand's cell; applied to its first
-- two arguments, the choice of conversion is made once.
operandReader :: Operand -> BasicType -> Word32 -> Value
operandReader op t = case op of
  OpBit _ _ b -> \w -> VBool (testBit w b) -- MT-MAP-13: a bit of the cell
  _
    | t == REAL -> \w -> VReal (realFromBits w)
    | otherwise -> wordToValue t
{-# INLINE operandReader #-}

-- | The pattern of the operand's cell after a write of the value, from the
-- pattern before it (only a bit operand looks at that): 'writeOperand' on a
-- pattern, masked to the cell's width.
operandWriter :: Operand -> Value -> Word32 -> Word32
operandWriter op = case op of
  OpBit _ _ b -> \v w -> case v of
    VBool x -> (if x then setBit w b else clearBit w b) .&. mask
    _ -> whole v
  _ -> \v _ -> whole v
  where
    !mask = cellMask (operandCell op)
    whole = \case
      VReal r -> realBits r .&. mask
      v -> valueToWord v .&. mask
{-# INLINE operandWriter #-}
