-- | MasterTool XE's PLC operands as data of the IEC core (docs/architecture.md,
-- "MasterTool XE on the IEC core"): what the IEC parser and checker need to
-- read a MasterTool module when the preset's source form is
-- 'Stref.Policy.MasterToolSource'.
--
-- An operand is a located variable of the core. Each operand kind is an
-- area of bytes of its own (the area letter is the operand's letter), and
-- operand n occupies the bytes n × w .. n × w + w - 1 of its area, w being
-- the operand's width in bytes (%E, %S, %A one, %M two, %I and %F four;
-- MT-MAP-17). A bit of %M n is a bit of one of its two bytes, the bytes
-- little-endian as in the core. The types Table 4-8 allows on an operand
-- have exactly its width (MT-MAP-5), so that no variable straddles two
-- operands and this byte layout cannot be told from a table of typed slots.
-- A table kind is an area too ('tableArea'), each table a row of 65536
-- positions in it; an array mapped onto an operand covers the row of
-- operands from it on ('operandTakes', MT-MAP-9).
module Stref.IEC.Dialect.MasterTool
  ( operandLocation
  , locationOperand
  , operandTypes
  , operandTakes
  , operandByteWidth
  , tableByteWidth
  , reservedWord
  , elementaryTypes
  , hasConversion
  , SignalUse (..)
  , signalUse
  , dataBytes
  , dataAreaLimit
  ) where

import qualified Data.Text as T
import Stref.Check (dataAreaLimit)
import Stref.Conversions (lookupConversionFunction)
import Stref.Lexical (WordClass (..), classifyWord)
import Stref.IEC.Syntax (Location (..))
import Stref.IEC.Types (Elem (..), Type (..))
import Stref.Operands (Operand (..), SimpleKind (..), TableKind (..), parseOperand, renderOperand, simpleLetter)
import Stref.Policy (Policies, overflowFlagName)

-- | The bytes of one operand of a kind (MT-MAP-17, Table 2-1).
operandByteWidth :: SimpleKind -> Integer
operandByteWidth = \case
  KE -> 1
  KS -> 1
  KA -> 1
  KM -> 2
  KI -> 4
  KF -> 4

-- | The bytes of one position of a table kind (MT-MAP-17: %TM holds words
-- as %M does, %TI and %TF double words as %I and %F).
tableByteWidth :: TableKind -> Integer
tableByteWidth = \case
  TM -> 2
  TI -> 4
  TF -> 4

-- | The area of a table kind (MT-MAP-2, MT-MAP-7): a character no simple
-- kind and no IEC area uses, the kind's letter in lower case. Table n is
-- the row of positions n × 65536 .. n × 65536 + 65535 of its kind's area (a
-- position is at most 65535, Stref.Operands), so that each table is an
-- area of its own named by its kind and number, and the positions an
-- array mapped onto a table covers are a row of bytes (MT-MAP-9).
tableArea :: TableKind -> Char
tableArea = \case
  TM -> 'm'
  TI -> 'i'
  TF -> 'f'

-- | An operand as the core's location: its bytes in its kind's area; the
-- text is the operand's canonical spelling (four-digit addresses).
operandLocation :: Operand -> Either T.Text Location
operandLocation op = case op of
  OpSimple k a -> Right (Location txt (letter k) (sizeOf k) [toInteger a * operandByteWidth k])
  -- MT-MAP-6: a bit of %E, %S, %A (0..7) or %M (0..15)
  OpBit k a b -> Right (Location txt (letter k) 'X' [toInteger a * operandByteWidth k + toInteger b `div` 8, toInteger b `mod` 8])
  -- MT-MAP-7: a table position
  OpTablePos k a p -> Right (Location txt (tableArea k) (if k == TM then 'W' else 'D') [(toInteger a * 65536 + toInteger p) * tableByteWidth k])
  where
    txt = renderOperand op
    letter = T.head . simpleLetter
    sizeOf = \case
      KM -> 'W'
      KI -> 'D'
      KF -> 'D'
      _ -> 'B'

-- | The operand a location of 'operandLocation' was made from (Nothing for
-- any other location).
locationOperand :: Location -> Maybe Operand
locationOperand l = either (const Nothing) Just (parseOperand (locText l))

-- | The types a variable mapped onto the location may have (MT-MAP-5,
-- MT-MAP-6: Table 4-8).
operandTypes :: Location -> [Elem]
operandTypes l = case locationOperand l of
  Just (OpBit {}) -> [BOOL]
  Just (OpSimple k _) -> case k of
    KM -> [INT, WORD]
    KI -> [DINT, DWORD]
    KF -> [REAL]
    _ -> [USINT, BYTE]
  Just (OpTablePos k _ _) -> case k of
    TM -> [INT, WORD]
    TI -> [DINT, DWORD]
    TF -> [REAL]
  _ -> []

-- | May a variable of the type be mapped onto the location? An elementary
-- type of Table 4-8 (MT-MAP-5, MT-MAP-6), or a one-dimensional array of one
-- (MT-MAP-9, MT-MAP-12) that is not BOOL (MT-MAP-11), which covers a row of
-- operands from the location on.
operandTakes :: Location -> Type -> Bool
operandTakes l = \case
  TArray [_] (TElem e) -> e /= BOOL && e `elem` operandTypes l
  TElem e -> e `elem` operandTypes l
  _ -> False

-- | A word a MasterTool declaration cannot take as its name (MT-LEX-17):
-- keywords, type names, standard function names, the predeclared signals
-- and INTERNAL_ names, as the MasterTool lexer classifies them.
--
-- The signals INPUT1..3 and OUTPUT1..3 (MT-SIG-1) and INTERNAL_OVERFLOW
-- (MT-OP-7) are left out: the controller declares them as globals
-- (Stref.IEC.Dialect.MasterToolCore), so that a program's own declaration
-- of one is a duplicate.
reservedWord :: Policies -> T.Text -> Bool
reservedWord pol w =
  let u = T.toUpper w
   in classifyWord pol u /= WPlain && classifyWord pol u /= WPredeclared

-- | MT-TYPE-1: the eight elementary types of MasterTool XE; the core's
-- others are not MasterTool's (unsupported-type).
elementaryTypes :: [Elem]
elementaryTypes = [BOOL, BYTE, WORD, DWORD, USINT, INT, DINT, REAL]

-- | MT-CONV-1..14 (Table 4-6): whether MasterTool has the conversion
-- function of this name (@INT_TO_REAL@; not @REAL_TO_BYTE@).
hasConversion :: T.Text -> Bool
hasConversion = maybe False (const True) . lookupConversionFunction

-- | How a module uses one of the controller's globals (MT-SIG-1, MT-SIG-2,
-- MT-OP-7): INPUT1..3 and INTERNAL_OVERFLOW are read only (MT-VERR-26),
-- OUTPUT1..3 written only (MT-VERR-25).
data SignalUse = ReadSignal | WriteSignal
  deriving (Eq, Show)

-- | The use of a signal, by its key (upper case); Nothing for another name.
signalUse :: T.Text -> Maybe SignalUse
signalUse k
  | k `elem` ["INPUT1", "INPUT2", "INPUT3", overflowFlagName] = Just ReadSignal
  | k `elem` ["OUTPUT1", "OUTPUT2", "OUTPUT3"] = Just WriteSignal
  | otherwise = Nothing

-- | MT-LIM-3 (A26): the bytes of data area an unmapped variable takes: a
-- BOOL one, the others their width, an array its elements'.
dataBytes :: Type -> Integer
dataBytes = \case
  TElem e -> elemBytes e
  TArray bs t -> product [hi - lo + 1 | (lo, hi) <- bs] * dataBytes t
  _ -> 0
  where
    elemBytes e
      | e `elem` [INT, WORD] = 2
      | e `elem` [DINT, DWORD, REAL] = 4
      | otherwise = 1
