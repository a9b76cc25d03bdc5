-- | Behaviour policies and dialect presets.
--
-- Every point where vendors differ, or where a manual is silent, is a field of
-- 'Policies' with enumerated alternatives; a dialect is a value of that record
-- ('presets'). The meaning functions take the record; nothing else in the
-- code asks which dialect it is running.
module Stref.Policy
  ( Policies (..)
  , citedIds
  , citing
  , Overflow (..)
  , ArithWidth (..)
  , DivZero (..)
  , RealDivZero (..)
  , RealOverflow (..)
  , ModZero (..)
  , ModSign (..)
  , RealToInt (..)
  , NarrowInt (..)
  , ImplicitConversions (..)
  , NameResolution (..)
  , ForBounds (..)
  , ForAtTypeMax (..)
  , ShortCircuit (..)
  , Lifetime (..)
  , IndexOutOfRange (..)
  , IdentifierLength (..)
  , NestedComments (..)
  , ElsifKeyword (..)
  , AfterError (..)
  , FTrigInitial (..)
  , DownCounterQ (..)
  , TimerQ (..)
  , InsertPosition (..)
  , StringBounds (..)
  , StringOverflow (..)
  , SubrangeCheck (..)
  , StandardLibrary (..)
  , Extensions (..)
  , ReservedNames (..)
  , Enumerations (..)
  , BitStringArithmetic (..)
  , ProgramCalls (..)
  , FBAccess (..)
  , SubrangeInitial (..)
  , TimeRange (..)
  , Model (..)
  , SourceForm (..)
  , OverflowFlag (..)
  , overflowFlagName
  , mastertoolXE
  , tecomat
  , nexto
  , presets
  , matiec
  , openplc
  , ironplc
  , rusty
  , lookupPreset
  , PolicyInfo (..)
  , policyTable
  , lookupPolicy
  , setPolicy
  , policyAssignments
  , alternativesOf
  ) where

import Data.List (find)
import Data.Text (Text)
import qualified Data.Text as T
import Text.Read (readMaybe)

-- | Integer result of + - * unary - EXPT out of range.
data Overflow = Saturate | Wrap | Trap
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Width of intermediate integer arithmetic.
data ArithWidth = OperandType | Promote32
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Integer @/@ by zero.
data DivZero = DivZeroError | DivZeroZero | DivZeroTrap
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | REAL @/@ by 0.0.
data RealDivZero = RealDivZeroError | RealDivZeroIeee
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | REAL result beyond the binary32 range.
data RealOverflow = RealOverflowSaturate | RealOverflowIeee
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | @x MOD 0@.
data ModZero = ModZeroZero | ModZeroError
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Sign of MOD (and rounding of @/@) with negative operands.
data ModSign = ModSignDividend | ModSignEuclidean
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | REAL to integer conversion.
data RealToInt = TruncateSaturate | RoundEvenSaturate | RoundEvenWrap
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Integer to narrower integer conversion.
data NarrowInt = NarrowWrap | NarrowSaturate
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Which conversions the checker inserts on its own.
data ImplicitConversions = ImplicitMastertool | ImplicitIecWidening | ImplicitCodesys | ImplicitNone
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | A local declared with a global's name.
data NameResolution = GlobalWins | LocalWins
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Are a FOR's TO and BY evaluated once or at every test?
data ForBounds = ForOnce | ForEveryIteration
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | A FOR whose end is the type's maximum.
data ForAtTypeMax = StopAtEnd | FollowOverflowPolicy
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Do AND/OR on BOOL evaluate their right operand when the left decides?
data ShortCircuit = Eager | ShortCircuit
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | State of unmapped variables between module calls.
data Lifetime = PerCall | Retained
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | An array index outside the bounds.
data IndexOutOfRange = IndexError | IndexClamp | IndexTrap
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Significant characters of an identifier.
data IdentifierLength = Significant Int | Unlimited
  deriving (Eq, Ord, Show)

data NestedComments = NoNesting | Nesting
  deriving (Eq, Ord, Show, Enum, Bounded)

data ElsifKeyword = ElsifOnly | ElsifAndElseif
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | After a runtime error in a scan cycle of an IEC program: does the
-- controller stop, or does the next cycle run?
data AfterError = StopController | ContinueNextCycle
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The initial value of F_TRIG's memory M (TC-FB-15: Tecomat TRUE; IEC FALSE).
data FTrigInitial = FTrigTrue | FTrigFalse
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The Q of CTD and the QD of CTUD: CV = 0 (TC-FB-19) or CV <= 0 (IEC).
data DownCounterQ = EqualZero | AtMostZero
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | When a TON or TP sees ET reach PT: Q in the same call, or in the next.
data TimerQ = SameCycle | NextCycle
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | INSERT(IN1, IN2, P): IN2 starts at position P (TC-STR-13) or after the
-- P-th character (IEC).
data InsertPosition = InsertAt | InsertAfter
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | String positions and lengths beyond the string: cut to it, or an error.
data StringBounds = StringClamp | StringBoundsError
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | A string longer than the capacity of its destination.
data StringOverflow = StringTruncate | StringOverflowError
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | A value outside a subrange on a store.
data SubrangeCheck = SubrangeError | SubrangeUnchecked
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The standard function blocks' library: IEC's (inputs S1, R, R1, LD;
-- counters on INT), or CODESYS's standard.library (inputs SET1, RESET,
-- RESET1, LOAD; counters on WORD: NX-FB-1, NX-FB-4, NX-FB-11).
data StandardLibrary = LibraryIec | LibraryCodesys
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The language beyond IEC 61131-3 ed.2: none, or CODESYS V3's (pointers,
-- methods, properties, actions, EXTENDS, JMP, CONTINUE, S=/R=, assignment
-- as an expression, pragmas).
data Extensions = ExtensionsNone | ExtensionsCodesys
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Which names a user declaration cannot take besides the keywords:
-- IEC's reading (types, standard functions and FBs, and their parameters'
-- names: TC-LEX-3, TC-LEX-4), or CODESYS's list (NX-LEX-12: types,
-- operators and functions, the IL operators such as S, R, LD, CAL; the
-- parameters' names are free).
data ReservedNames = ReservedIec | ReservedCodesys
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | What an enumerated value is: a name of its type (IEC: TC-TYPE-21), or
-- a number of the type's base type, INT unless stated (CODESYS:
-- NX-TYPE-57..67), which mixes with numbers.
data Enumerations = EnumSymbolic | EnumInteger
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Do + - * / MOD take bit strings (BYTE, WORD, DWORD, LWORD)? IEC: no,
-- they are not numbers (TC-TYPE-14 of the catalogue's IEC reading);
-- CODESYS: yes, modulo 2^n (NX-OP-23, NX-OP-30).
data BitStringArithmetic = BitArithmeticNo | BitArithmeticYes
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | May a POU call a PROGRAM (which then keeps its state between calls)?
-- IEC/Tecomat: no, tasks run programs (TC-POU-44); CODESYS: yes, from
-- programs and function blocks, not from functions (NX-POU-2..4).
data ProgramCalls = ProgramCallsForbidden | ProgramCallsAllowed
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Who may write an FB's inputs and outputs: IEC/Tecomat: an input is
-- read-only inside its POU (TC-VAR-1) and an output outside the instance
-- (TC-POU-24); CODESYS: both are plain variables of the instance.
data FBAccess = AccessIec | AccessCodesys
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The initial value of a subrange variable declared without one: its
-- lower bound (IEC: TC-TYPE-21), or 0 when the range holds 0 (CODESYS:
-- "the default initial value is 0 for all declarations", NX-TYPE-35).
-- | What a TIME holds: a signed 32-bit count of milliseconds (IEC,
-- TC-TYPE-19), or an unsigned one, a DWORD (CODESYS, NX-TYPE-30), in which
-- a negative duration does not exist and a result below 0 wraps or
-- saturates like any other overflow.
data TimeRange = TimeSigned | TimeUnsigned
  deriving (Eq, Ord, Show, Enum, Bounded)

data SubrangeInitial = SubrangeLowerBound | SubrangeZero
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The controller a dialect runs on: MasterTool's (operand tables, CHF
-- parameters, per-call initialisation, the diagnostic band) or IEC
-- 61131-3's (program instances, tasks, a clock). Part of the preset, not a
-- choice of the command line.
data Model = MasterToolController | IecController
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | How the dialect writes a compilation unit, for the IEC parser and
-- checker: IEC 61131-3's (TYPE, VAR_GLOBAL, POUs, direct addresses %IX0.1,
-- Tecomat's %X0.2), or a MasterTool XE module (global VAR blocks before the
-- one PROGRAM, MT-POU-1; PLC operands %M0010, %M0010.3, %F0002, MT-MAP-2,
-- Stref.IEC.Dialect.MasterTool). Part of the preset, like the model.
data SourceForm = IecSource | MasterToolSource
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Does the controller keep a flag of the last arithmetic overflow? None
-- (IEC), or MasterTool XE's INTERNAL_OVERFLOW (MT-OP-7): a BOOL global the
-- controller declares, which every +, -, *, unary - and EXPT sets to whether
-- it overflowed and every other operation leaves. Part of the preset, like
-- the model: the flag is a variable of the controller.
data OverflowFlag = NoOverflowFlag | InternalOverflowFlag
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | The name of the global 'InternalOverflowFlag' keeps (MT-OP-7, MT-SIG-6).
overflowFlagName :: Text
overflowFlagName = "INTERNAL_OVERFLOW"

data Policies = Policies
  { pModel :: !Model
  , pSourceForm :: !SourceForm
  , pOverflowFlag :: !OverflowFlag
  , pCallDepth :: !Int
  -- ^ the most calls that may be nested; one more is the runtime error
  -- @call-depth@. Part of the preset, like the model
  , pOverflow :: !Overflow
  , pArithWidth :: !ArithWidth
  , pDivZero :: !DivZero
  , pRealDivZero :: !RealDivZero
  , pRealOverflow :: !RealOverflow
  , pModZero :: !ModZero
  , pModSign :: !ModSign
  , pRealToInt :: !RealToInt
  , pNarrowInt :: !NarrowInt
  , pImplicitConversions :: !ImplicitConversions
  , pNameResolution :: !NameResolution
  , pForBounds :: !ForBounds
  , pForAtTypeMax :: !ForAtTypeMax
  , pShortCircuit :: !ShortCircuit
  , pLifetime :: !Lifetime
  , pIndexOutOfRange :: !IndexOutOfRange
  , pIdentifierLength :: !IdentifierLength
  , pNestedComments :: !NestedComments
  , pElsifKeyword :: !ElsifKeyword
  , pErrorLineBeforeStart :: !Int
  -- ^ decision A2: the line written for an error found before the first
  -- statement (EN Rev. C: 0; the earlier PT revision: -1)
  , pStepBudget :: !Int
  -- ^ MT-EXEC-7: the execution-time limit, as a deterministic count of
  -- executed statements and loop tests; exceeding it is runtime error 2030
  , pAfterError :: !AfterError
  , pFTrigInitial :: !FTrigInitial
  , pDownCounterQ :: !DownCounterQ
  , pTimerQ :: !TimerQ
  , pInsertPosition :: !InsertPosition
  , pStringBounds :: !StringBounds
  , pStringOverflow :: !StringOverflow
  , pStringLength :: !Int
  -- ^ the capacity of a STRING declared without one
  , pArrayDimensions :: !Int
  -- ^ the most dimensions an array may have
  , pSubrange :: !SubrangeCheck
  , pStandardLibrary :: !StandardLibrary
  , pExtensions :: !Extensions
  , pReservedNames :: !ReservedNames
  , pEnumerations :: !Enumerations
  , pBitStringArithmetic :: !BitStringArithmetic
  , pProgramCalls :: !ProgramCalls
  , pFBAccess :: !FBAccess
  , pSubrangeInitial :: !SubrangeInitial
  , pTimeRange :: !TimeRange
  , pCatalogue :: Text
  -- ^ the prefix of the rule ids of the dialect's catalogue (MT, TC, NX):
  -- the ids a trace cites where a rule has one in several catalogues.
  -- Lazy: a strict Text would make each preset a CAF, which the evaluators
  -- then enter at every use of a policy
  }
  deriving (Eq, Show)

-- | The MasterTool XE preset (catalogue §15 decisions; policies.md column).
mastertoolXE :: Policies
mastertoolXE =
  Policies
    { pModel = MasterToolController
    , pSourceForm = MasterToolSource -- MT-POU-1, MT-MAP-2
    , pOverflowFlag = InternalOverflowFlag -- MT-OP-7
    , pCallDepth = 16 -- MT-POU-9, MT-LIM-1, MT-ERR-2050
    , pOverflow = Saturate -- MT-OP-6, MT-OP-7
    , pArithWidth = OperandType -- MT-OP-4
    , pDivZero = DivZeroError -- MT-OP-9
    , pRealDivZero = RealDivZeroError -- A6
    , pRealOverflow = RealOverflowSaturate -- A6
    , pModZero = ModZeroZero -- MT-OP-8
    , pModSign = ModSignDividend -- A7
    , pRealToInt = TruncateSaturate -- MT-CONV-9, C52, C53
    , pNarrowInt = NarrowWrap -- C37-C47
    , pImplicitConversions = ImplicitMastertool -- MT-CONV-6
    , pNameResolution = GlobalWins -- MT-SCOPE-5
    , pForBounds = ForOnce -- MT-STMT-19, A14
    , pForAtTypeMax = StopAtEnd -- A13
    , pShortCircuit = Eager -- A17
    , pLifetime = PerCall -- MT-MAP-1, MT-SCOPE-7
    , pIndexOutOfRange = IndexError -- MT-ARR-8
    , pIdentifierLength = Significant 32 -- MT-LEX-4
    , pNestedComments = NoNesting -- MT-LEX-8
    , pElsifKeyword = ElsifAndElseif -- A1
    , pErrorLineBeforeStart = 0 -- A2
    , pStepBudget = 10000000 -- MT-EXEC-7: 10^7 steps, far above any terminating program of realistic size
    -- the IEC policies: MasterTool has no FBs, strings or subranges; these
    -- are the IEC readings, never observable in a MasterTool program
    , pAfterError = ContinueNextCycle -- MT-DIAG-2: the controller keeps scanning
    , pFTrigInitial = FTrigFalse
    , pDownCounterQ = AtMostZero
    , pTimerQ = SameCycle
    , pInsertPosition = InsertAfter
    , pStringBounds = StringClamp
    , pStringOverflow = StringTruncate
    , pStringLength = 80
    , pArrayDimensions = 1 -- MT-TYPE-3, MT-TYPE-4
    , pSubrange = SubrangeError
    , pStandardLibrary = LibraryIec
    , pExtensions = ExtensionsNone
    , pReservedNames = ReservedIec
    , pEnumerations = EnumSymbolic
    , pBitStringArithmetic = BitArithmeticNo
    , pProgramCalls = ProgramCallsForbidden
    , pFBAccess = AccessIec
    , pSubrangeInitial = SubrangeLowerBound
    , pTimeRange = TimeSigned
    , pCatalogue = "MT"
    }

-- | The Tecomat preset (docs/tecomat.md gives the reason for each choice).
tecomat :: Policies
tecomat =
  Policies
    { pModel = IecController
    , pSourceForm = IecSource
    , pOverflowFlag = NoOverflowFlag
    , pCallDepth = 1000 -- TC-ERR-6: the manual gives no number; deep enough for any program that ends
    , pOverflow = Wrap -- TC-OP-20
    , pArithWidth = OperandType -- TC-CONV-2
    , pDivZero = DivZeroError -- TC-OP-22
    , pRealDivZero = RealDivZeroIeee -- TC-TYPE-8, TC-OP-26
    , pRealOverflow = RealOverflowIeee -- TC-TYPE-8, TC-OP-26
    , pModZero = ModZeroZero -- TC-OP-24
    , pModSign = ModSignDividend -- TC-OP-21, TC-OP-23
    , pRealToInt = RoundEvenSaturate -- TC-CONV-12
    , pNarrowInt = NarrowWrap -- TC-CONV-13
    , pImplicitConversions = ImplicitNone -- TC-CONV-1, TC-CONV-3
    , pNameResolution = LocalWins -- TC-VAR-33
    , pForBounds = ForEveryIteration -- TC-STMT-26
    , pForAtTypeMax = FollowOverflowPolicy -- TC-STMT-31
    , pShortCircuit = Eager -- TC-OP-6
    , pLifetime = Retained -- TC-VAR-7, TC-POU-15
    , pIndexOutOfRange = IndexError -- TC-ERR-3
    , pIdentifierLength = Significant 64 -- TC-LEX-16, TC-LEX-17
    , pNestedComments = NoNesting -- TC-LEX-8
    , pElsifKeyword = ElsifOnly -- TC-STMT-9
    , pErrorLineBeforeStart = 0
    , pStepBudget = 1000000 -- TC-ERR-1: the cycle error, as a deterministic count of steps per cycle
    , pAfterError = StopController -- TC-STMT-35
    , pFTrigInitial = FTrigTrue -- TC-FB-15
    , pDownCounterQ = EqualZero -- TC-FB-19
    , pTimerQ = SameCycle -- TC-FB-27
    , pInsertPosition = InsertAt -- TC-STR-13
    , pStringBounds = StringClamp -- TC-STR-15..17
    , pStringOverflow = StringTruncate -- TC-TYPE-27, TC-STR-18
    , pStringLength = 255 -- TC-TYPE-26
    , pArrayDimensions = 4 -- TC-TYPE-39
    , pSubrange = SubrangeError -- TC-TYPE-33
    , pStandardLibrary = LibraryIec -- TC-FB-2..8
    , pExtensions = ExtensionsNone
    , pReservedNames = ReservedIec -- TC-LEX-3, TC-LEX-4
    , pEnumerations = EnumSymbolic -- TC-TYPE-21, TC-TYPE-36
    , pBitStringArithmetic = BitArithmeticNo -- TC-OP-12
    , pProgramCalls = ProgramCallsForbidden -- TC-POU-44
    , pFBAccess = AccessIec -- TC-VAR-1, TC-POU-24
    , pSubrangeInitial = SubrangeLowerBound -- TC-TYPE-21
    , pTimeRange = TimeSigned -- TC-TYPE-19
    , pCatalogue = "TC"
    }

-- | The Nexto preset: CODESYS V3 as the Nexto manual documents it
-- (docs/nexto.md gives the reason for each choice).
nexto :: Policies
nexto =
  tecomat
    { pOverflow = Wrap -- NX-OP-32, NX-DIFF-4
    , pArithWidth = OperandType -- NX-OP-50
    , pDivZero = DivZeroError -- NX-OP-29, NX-ERR-10
    , pRealDivZero = RealDivZeroIeee -- NX-TYPE-23
    , pRealOverflow = RealOverflowIeee -- NX-TYPE-23
    , pModZero = ModZeroError -- NX-OP-30, NX-DIFF-10
    , pModSign = ModSignDividend -- NX-OP-28
    , pRealToInt = RoundEvenWrap -- NX-CONV-21..24
    , pNarrowInt = NarrowWrap -- NX-CONV-19
    , pImplicitConversions = ImplicitCodesys -- NX-CONV-1..5
    , pNameResolution = LocalWins -- NX-VAR-33
    , pForBounds = ForEveryIteration -- NX-STMT-25
    , pForAtTypeMax = FollowOverflowPolicy -- NX-STMT-21
    , pShortCircuit = Eager -- NX-OP-22
    , pLifetime = Retained -- NX-POU-1, NX-POU-16
    , pIndexOutOfRange = IndexError -- NX-ERR-9
    , pIdentifierLength = Unlimited -- NX-LEX-5
    , pNestedComments = Nesting -- NX-LEX-17
    , pElsifKeyword = ElsifOnly -- NX-STMT-11
    , pStepBudget = 1000000 -- NX-TASK-3: the task watchdog, as a count of steps per cycle
    , pAfterError = StopController -- NX-ERR-1
    , pFTrigInitial = FTrigFalse -- NX-FB-10: M starts FALSE, so a first FALSE is an edge
    , pDownCounterQ = EqualZero -- NX-FB-15
    , pTimerQ = SameCycle -- NX-FB-26
    , pInsertPosition = InsertAfter -- NX-STR-7
    , pStringBounds = StringClamp -- NX-STR-11
    , pStringOverflow = StringTruncate -- NX-TYPE-26, NX-TYPE-27
    , pStringLength = 80 -- NX-TYPE-24
    , pArrayDimensions = 3 -- NX-TYPE-42
    , pSubrange = SubrangeUnchecked -- NX-TYPE-71, NX-ERR-17
    , pStandardLibrary = LibraryCodesys -- NX-FB-1, NX-FB-4, NX-FB-11
    , pExtensions = ExtensionsCodesys
    , pReservedNames = ReservedCodesys -- NX-LEX-12, NX-LEX-13
    , pEnumerations = EnumInteger -- NX-TYPE-60..66
    , pBitStringArithmetic = BitArithmeticYes -- NX-OP-23, NX-OP-30
    , pProgramCalls = ProgramCallsAllowed -- NX-POU-2..4
    , pFBAccess = AccessCodesys -- NX-POU-19
    , pSubrangeInitial = SubrangeZero -- NX-TYPE-35
    , pTimeRange = TimeUnsigned -- NX-TYPE-30, NX-TYPE-34
    , pCatalogue = "NX"
    }

-- | An engine's preset: what MATIEC's upstream head does where the IEC
-- language leaves a choice, found by running the tecomat corpus against it
-- (docs/engines.md gives the evidence for each).
matiec :: Policies
matiec =
  tecomat
    { pFTrigInitial = FTrigFalse -- F_TRIG's memory starts FALSE: a first FALSE CLK is an edge
    , pStringLength = 126 -- every STRING holds 126 characters
    , pSubrange = SubrangeUnchecked -- a subrange's check function is generated but never called
    }

-- | OpenPLC's fork of MATIEC: as upstream, but F_TRIG gives no edge before
-- a rising one.
openplc :: Policies
openplc = matiec {pFTrigInitial = FTrigTrue}

-- | IronPLC (ironplcc and ironplcvm 0.239.0): intermediate results in 32
-- bits, MOD by 0 stops the VM like a division, REAL to integer truncates,
-- subranges unchecked (docs/engines.md).
ironplc :: Policies
ironplc =
  tecomat
    { pArithWidth = Promote32 -- (a + b) / 2 of two INT 20000 is 20000
    , pModZero = ModZeroError -- trap V4001, as for /
    , pRealToInt = TruncateSaturate -- REAL_TO_INT(1.5) is 1, (-2.7) is -2
    , pSubrange = SubrangeUnchecked -- an INT (0..10) takes 11 without an error
    }

-- | RuSTy (plc, commit 8dc2c0e): its timers end when the elapsed time
-- passes PT, a cycle after IEC's; STRING holds 80 characters; MOD by 0
-- traps like a division; subranges unchecked; CTD's Q is CV <= 0
-- (docs/engines.md).
rusty :: Policies
rusty =
  tecomat
    { pTimerQ = NextCycle -- TON(PT := T#30ms) at 10 ms: Q in the cycle at 40 ms, not 30
    , pStringLength = 80 -- STRING is 81 bytes
    , pModZero = ModZeroError -- SIGFPE, as for /
    , pSubrange = SubrangeUnchecked -- no check is generated
    , pDownCounterQ = AtMostZero -- CTD's Q stays TRUE below 0 (ctd-below-zero)
    }

-- | Named presets: each dialect is an entry here, not a fork of the code;
-- so is each real engine's behaviour (docs/engines.md).
presets :: [(Text, Policies)]
presets = [("mastertool-xe", mastertoolXE), ("tecomat", tecomat), ("nexto", nexto), ("matiec", matiec), ("openplc", openplc), ("ironplc", ironplc), ("rusty", rusty)]

lookupPreset :: Text -> Maybe Policies
lookupPreset n = lookup n presets

-- | One policy: its name on the command line and in the corpus (@expect-if@),
-- its alternatives, and how to read and set it in the record.
data PolicyInfo = PolicyInfo
  { piName :: Text
  , piAlternatives :: [Text] -- ^ empty for numeric policies
  , piGet :: Policies -> Text
  , piSet :: Text -> Policies -> Maybe Policies
  }

-- | An enumerated policy from its names, in the order of its constructors.
enumPolicy :: (Eq e, Enum e, Bounded e) => Text -> [Text] -> (Policies -> e) -> (e -> Policies -> Policies) -> PolicyInfo
enumPolicy name names get set =
  PolicyInfo
    { piName = name
    , piAlternatives = names
    , piGet = \p -> maybe "?" snd (find ((== get p) . fst) table)
    , piSet = \v p -> (`set` p) . fst <$> find ((== v) . snd) table
    }
  where
    table = zip [minBound .. maxBound] names

numPolicy :: Text -> (Policies -> Int) -> (Int -> Policies -> Policies) -> PolicyInfo
numPolicy name get set =
  PolicyInfo name [] (T.pack . show . get) (\v p -> (`set` p) <$> readMaybe (T.unpack v))

policyTable :: [PolicyInfo]
policyTable =
  [ enumPolicy "overflow" ["saturate", "wrap", "trap"] pOverflow (\v p -> p {pOverflow = v})
  , enumPolicy "arith-width" ["operand-type", "promote-32"] pArithWidth (\v p -> p {pArithWidth = v})
  , enumPolicy "div-zero" ["error", "zero", "trap"] pDivZero (\v p -> p {pDivZero = v})
  , enumPolicy "real-div-zero" ["error", "ieee"] pRealDivZero (\v p -> p {pRealDivZero = v})
  , enumPolicy "real-overflow" ["saturate", "ieee"] pRealOverflow (\v p -> p {pRealOverflow = v})
  , enumPolicy "mod-zero" ["zero", "error"] pModZero (\v p -> p {pModZero = v})
  , enumPolicy "mod-sign" ["dividend", "euclidean"] pModSign (\v p -> p {pModSign = v})
  , enumPolicy "real-to-int" ["truncate-saturate", "round-even-saturate", "round-even-wrap"] pRealToInt (\v p -> p {pRealToInt = v})
  , enumPolicy "narrow-int" ["wrap", "saturate"] pNarrowInt (\v p -> p {pNarrowInt = v})
  , enumPolicy "implicit-conversions" ["mastertool", "iec-widening", "codesys", "none"] pImplicitConversions (\v p -> p {pImplicitConversions = v})
  , enumPolicy "name-resolution" ["global-wins", "local-wins"] pNameResolution (\v p -> p {pNameResolution = v})
  , enumPolicy "for-bounds" ["once", "every-iteration"] pForBounds (\v p -> p {pForBounds = v})
  , enumPolicy "for-at-type-max" ["stop-at-end", "follow-overflow-policy"] pForAtTypeMax (\v p -> p {pForAtTypeMax = v})
  , enumPolicy "short-circuit" ["eager", "short-circuit"] pShortCircuit (\v p -> p {pShortCircuit = v})
  , enumPolicy "lifetime" ["per-call", "retained"] pLifetime (\v p -> p {pLifetime = v})
  , enumPolicy "index-out-of-range" ["error", "clamp", "trap"] pIndexOutOfRange (\v p -> p {pIndexOutOfRange = v})
  , PolicyInfo
      { piName = "identifier-length"
      , piAlternatives = []
      , piGet = \p -> case pIdentifierLength p of
          Unlimited -> "unlimited"
          Significant n -> T.pack (show n)
      , piSet = \v p -> case v of
          "unlimited" -> Just p {pIdentifierLength = Unlimited}
          _ -> case readMaybe (T.unpack v) of
            Just n | n > 0 -> Just p {pIdentifierLength = Significant n}
            _ -> Nothing
      }
  , enumPolicy "nested-comments" ["no", "yes"] pNestedComments (\v p -> p {pNestedComments = v})
  , enumPolicy "elsif-keyword" ["ELSIF", "ELSIF+ELSEIF"] pElsifKeyword (\v p -> p {pElsifKeyword = v})
  , numPolicy "error-line-before-start" pErrorLineBeforeStart (\v p -> p {pErrorLineBeforeStart = v})
  , numPolicy "step-budget" pStepBudget (\v p -> p {pStepBudget = max 1 v})
  , enumPolicy "after-error" ["stop", "continue"] pAfterError (\v p -> p {pAfterError = v})
  , enumPolicy "f-trig-initial" ["true", "false"] pFTrigInitial (\v p -> p {pFTrigInitial = v})
  , enumPolicy "down-counter-q" ["equal-zero", "at-most-zero"] pDownCounterQ (\v p -> p {pDownCounterQ = v})
  , enumPolicy "timer-q" ["same-cycle", "next-cycle"] pTimerQ (\v p -> p {pTimerQ = v})
  , enumPolicy "insert-position" ["at", "after"] pInsertPosition (\v p -> p {pInsertPosition = v})
  , enumPolicy "string-bounds" ["clamp", "error"] pStringBounds (\v p -> p {pStringBounds = v})
  , enumPolicy "string-overflow" ["truncate", "error"] pStringOverflow (\v p -> p {pStringOverflow = v})
  , numPolicy "string-length" pStringLength (\v p -> p {pStringLength = max 1 v})
  , numPolicy "array-dimensions" pArrayDimensions (\v p -> p {pArrayDimensions = max 1 v})
  , enumPolicy "subrange" ["error", "unchecked"] pSubrange (\v p -> p {pSubrange = v})
  , enumPolicy "standard-library" ["iec", "codesys"] pStandardLibrary (\v p -> p {pStandardLibrary = v})
  , enumPolicy "extensions" ["none", "codesys"] pExtensions (\v p -> p {pExtensions = v})
  , enumPolicy "reserved-names" ["iec", "codesys"] pReservedNames (\v p -> p {pReservedNames = v})
  , enumPolicy "enumerations" ["symbolic", "integer"] pEnumerations (\v p -> p {pEnumerations = v})
  , enumPolicy "bit-string-arithmetic" ["no", "yes"] pBitStringArithmetic (\v p -> p {pBitStringArithmetic = v})
  , enumPolicy "program-calls" ["forbidden", "allowed"] pProgramCalls (\v p -> p {pProgramCalls = v})
  , enumPolicy "fb-access" ["iec", "codesys"] pFBAccess (\v p -> p {pFBAccess = v})
  , enumPolicy "subrange-initial" ["lower-bound", "zero"] pSubrangeInitial (\v p -> p {pSubrangeInitial = v})
  , enumPolicy "time-range" ["signed", "unsigned"] pTimeRange (\v p -> p {pTimeRange = v})
  ]

lookupPolicy :: Text -> Maybe PolicyInfo
lookupPolicy n = find ((== n) . piName) policyTable

-- | @setPolicy "overflow" "wrap" p@; a clear message for an unknown name or
-- alternative.
setPolicy :: Text -> Text -> Policies -> Either Text Policies
setPolicy name value p = case lookupPolicy name of
  Nothing ->
    Left ("unknown policy '" <> name <> "'; the policies are: " <> T.intercalate ", " (map piName policyTable))
  Just info -> case piSet info value p of
    Just p' -> Right p'
    Nothing ->
      Left
        ( "policy '" <> name <> "' has no alternative '" <> value <> "'"
            <> if null (piAlternatives info)
              then "; it takes a number"
              else "; the alternatives are: " <> T.intercalate ", " (piAlternatives info)
        )

-- | Every policy with its current choice, in table order.
policyAssignments :: Policies -> [(Text, Text)]
policyAssignments p = [(piName i, piGet i p) | i <- policyTable]

-- | The records obtained by setting one policy to each of its alternatives.
alternativesOf :: Text -> Policies -> Either Text [(Text, Policies)]
alternativesOf name p = case lookupPolicy name of
  Nothing -> Left ("unknown policy '" <> name <> "'")
  Just info
    | null (piAlternatives info) -> Left ("policy '" <> name <> "' is numeric; it has no list of alternatives")
    | otherwise -> traverse (\a -> (a,) <$> setPolicy name a p) (piAlternatives info)

-- | The rule ids cited under these policies: those of the dialect's
-- catalogue ('pCatalogue'), or all of them when it has none; a message or a
-- trace names the rule as its reader's catalogue numbers it.
citedIds :: Policies -> [Text] -> [Text]
citedIds pol ids = case filter ((pCatalogue pol <> "-") `T.isPrefixOf`) ids of
  [] -> ids
  mine -> mine

-- | A message's citation of rules, @(TC-CONV-1, TC-CONV-3)@.
citing :: Policies -> [Text] -> Text
citing pol ids = "(" <> T.intercalate ", " (citedIds pol ids) <> ")"
