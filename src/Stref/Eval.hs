{-# OPTIONS_GHC -O2 #-}
-- (the interpreter's hot path: bench/RESULTS.md measures -O2 against -O1)
-- | The meaning of checked expressions and statements (catalogue §§ 5, 6, 8).
--
-- Denotational style: every 'CExpr' and 'CStmt' is translated ONCE into a
-- Haskell closure over the machine state ('Exec'); running a loop runs the
-- closure again, it never walks the tree again. The policies are fixed at
-- translation time, so a closure already is the meaning under one dialect.
--
-- Everything here is pure: the closures run in 'ST' over a machine of
-- mutable slots (variables resolved to vector indices when the closure is
-- built), and a module call is one 'runST'. A runtime error stops the
-- closures; the machine keeps the state at the moment it occurred (operand
-- writes made before an error persist, MT-EXEC-8).
--
-- A module translated with tracing on ('compileTracedModule') is made of
-- other closures (the section "Tracing" at the end): the reference
-- operators of "Stref.Operators" instead of the fast paths, and each
-- closure tells the machine's tracer what it read, wrote and decided. The
-- fast closures are the same whether or not a traced translation exists.
{-# LANGUAGE MagicHash #-}
{-# LANGUAGE RankNTypes #-}
{-# LANGUAGE UnboxedTuples #-}
module Stref.Eval
  ( -- * The machine
    Machine (..)
  , newMachine
  , Snapshot (..)
  , snapshot
  , snapshotElement
  , Env (..)
  , Res (..)
  , Exec (..)
  , failWith
  , getMemory
  , writeMachineCell
  , maxCallDepth
  , errMalformed
    -- * Variables
  , readScalar
  , writeScalar
  , readElement
  , writeElement
  , elementOperand
  , varElements
  , initVar
    -- * Translation
  , Flow (..)
  , CompiledModule (..)
  , compileModule
  , compileTracedModule
  , compileExpr
    -- * Tracing
  , traceEvent
  , compileBlock
  ) where

import Control.Monad.ST (ST, runST)
import Data.Bits (xor, (.&.), (.|.))
import GHC.Exts (Float (F#), Float#, Int (I#), Int#, SmallArray#, SmallMutableArray#, State#, newSmallArray#, readSmallArray#, sizeofSmallArray#, sizeofSmallMutableArray#, thawSmallArray#, unsafeFreezeSmallArray#, writeSmallArray#)
import GHC.ST (ST (..))
import qualified Data.IntMap.Strict as IM
import Data.Int (Int16, Int32)
import Data.IntMap.Strict (IntMap)
import Data.List (partition)
import Data.STRef
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import qualified Data.Vector as V
import qualified Data.Vector.Mutable as MV
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU
import Stref.Checked
import Stref.Conversions (conversionName, convert)
import Stref.Diagnostics
import Stref.Eval.Fast
import Stref.Numeric (realToRational)
import Stref.Operands
import qualified Stref.Operators as O
import Stref.Policy
import Stref.Trace (Decision, Event (..), Tracer, decision, emit, newTracer, ruled)
import Stref.Types
import Stref.Values

-- | The state one module call works on: mutable slots, valid inside one
-- 'runST'.
data Machine s = Machine
  { mData :: {-# UNPACK #-} !(MV.MVector s Value) -- ^ the module data area (MT-MAP-1)
  , mFrame :: {-# UNPACK #-} !(STRef s (CallFrame s)) -- ^ the active function call's frame (MT-SCOPE-7)
  , mMemory :: {-# UNPACK #-} !(STRef s Memory) -- ^ the PLC operands, but for those of 'mCells'
  , mCellSlots :: !CellSlots -- ^ the module's mapped cells ...
  , mCells :: {-# UNPACK #-} !(MU.MVector s Int) -- ^ ... and their patterns during the call ('heldPattern')
  , mCounters :: {-# UNPACK #-} !(MU.MVector s Int)
  -- ^ steps used of the budget (MT-EXEC-7), INTERNAL_OVERFLOW (MT-OP-7),
  -- OUTPUT1..3 (MT-SIG-4), whether a runtime error occurred, at the
  -- indices below
  , mError :: {-# UNPACK #-} !(STRef s RuntimeError) -- ^ the runtime error, once one occurred
  , mTrace :: !(Maybe (STRef s Tracer))
  -- ^ the events of a traced translation (the fast closures never touch it)
  }

ixSteps, ixOverflow, ixFailed :: Int
ixSteps = 0
ixOverflow = 1
ixFailed = 5

-- | OUTPUTn is counter 1 + n.
ixOutput :: Int -> Int
ixOutput n = 1 + n

-- | A machine with the data area taken from the retained slots, or else
-- every slot at its type default (so reading a slot before any write gives
-- the default, as MT-VAR-3 asks); OUTPUT1 TRUE, the others and the flag
-- FALSE, no steps used.
newMachine :: CompiledModule -> CellSlots -> IntMap Value -> Memory -> (Bool, Bool, Bool) -> ST s (Machine s)
newMachine cm table retained mem (o1, o2, o3) = do
  d <-
    V.thaw $
      if IM.null retained
        then cmDataDefaults cm
        else V.imap (\k def -> IM.findWithDefault def k retained) (cmDataDefaults cm)
  f <- newFrame 0
  fr <- newSTRef f
  let (rest, held) = takeCells table mem
  mr <- newSTRef rest
  cells <- U.thaw held
  cs <- MU.replicate 6 0
  MU.write cs (ixOutput 1) (fromEnum o1)
  MU.write cs (ixOutput 2) (fromEnum o2)
  MU.write cs (ixOutput 3) (fromEnum o3)
  er <- newSTRef (runtimeError errMalformed 0)
  -- a machine of an untraced translation allocates no tracer
  tr <- if cmTraced cm then Just <$> newSTRef (newTracer False) else pure Nothing
  pure (Machine d fr mr table cells cs er tr)

-- | The machine's state after a call, immutable.
data Snapshot = Snapshot
  { snData :: !(V.Vector Value)
  , snMemory :: !Memory
  , snOutputs :: !(Bool, Bool, Bool)
  , snOverflow :: !Bool
  , snSteps :: !Int
  }

snapshot :: Machine s -> ST s Snapshot
snapshot m = do
  d <- V.freeze (mData m)
  mem <- currentMemory m
  let counter = MU.unsafeRead (mCounters m)
  steps <- counter ixSteps
  o <- counter ixOverflow
  a <- counter (ixOutput 1)
  b <- counter (ixOutput 2)
  c <- counter (ixOutput 3)
  pure (Snapshot d mem (a /= 0, b /= 0, c /= 0) (o /= 0) steps)

-- | Element @off@ of a variable in a snapshot; frame variables (no frame is
-- active after a call) and INPUTn read their defaults.
snapshotElement :: Env -> Snapshot -> Var -> Int -> Value
snapshotElement env sn v off = case varHome v of
  Data i -> maybe def id (snData sn V.!? (i + off))
  Frame _ -> def
  Mapped o -> readOperand (snMemory sn) (elementOperand o off) (varBasicType v)
  SignalInput n -> VBool (signal n (envInputs env))
  SignalOutput n -> VBool (signal n (snOutputs sn))
  OverflowFlag -> VBool (snOverflow sn)
  where
    def = defaultValue (varBasicType v)

-- | What does not change while a closure runs: the module inputs and the
-- number of active function frames.
data Env = Env
  { envInputs :: !(Bool, Bool, Bool) -- ^ INPUT1..3 (MT-SIG-2)
  , envDepth :: !Int -- ^ active function frames (decision A27)
  }
  deriving (Eq, Show)

-- | The outcome of running a closure: a value, or a runtime error (the
-- machine holds the state at the moment of the error).
data Res a
  = Done !a
  | Failed !RuntimeError

-- | A reader of the environment and an error monad over 'ST', written out
-- so that it stays small and fast.
newtype Exec s a = Exec {unExec :: Env -> Machine s -> ST s (Res a)}

instance Functor (Exec s) where
  fmap f (Exec g) = Exec $ \e m ->
    g e m >>= \case
      Done a -> pure (Done (f a))
      Failed x -> pure (Failed x)
  {-# INLINE fmap #-}

instance Applicative (Exec s) where
  pure a = Exec $ \_ _ -> pure (Done a)
  {-# INLINE pure #-}
  Exec f <*> Exec g = Exec $ \e m ->
    f e m >>= \case
      Failed x -> pure (Failed x)
      Done h ->
        g e m >>= \case
          Failed x -> pure (Failed x)
          Done a -> pure (Done (h a))
  {-# INLINE (<*>) #-}

instance Monad (Exec s) where
  Exec g >>= k = Exec $ \e m ->
    g e m >>= \case
      Failed x -> pure (Failed x)
      Done a -> unExec (k a) e m
  {-# INLINE (>>=) #-}

failWith :: ErrorCode -> Line -> Exec s a
failWith c l = Exec $ \_ _ -> pure (Failed (runtimeError c l))

getMemory :: Exec s Memory
getMemory = Exec $ \_ m -> Done <$> currentMemory m

-- | The PLC operands now: the memory with the mapped cells' patterns.
currentMemory :: Machine s -> ST s Memory
currentMemory m = do
  rest <- readSTRef (mMemory m)
  held <- U.freeze (mCells m)
  pure (putCells (mCellSlots m) held rest)

-- | Write a cell's pattern (masked to its width) into the machine, given
-- its slot in the machine's table ('lookupSlot', -1 for a cell the table
-- does not hold): the diagnostic band at the end of a call.
writeMachineCell :: Machine s -> Cell -> Int -> Word32 -> ST s ()
writeMachineCell m c j w
  | j >= 0 = writeCellValue (mCells m) j (w .&. cellMask c)
  | otherwise = modifySTRef' (mMemory m) (writeCell c w)

readCellValue :: MU.MVector s Int -> Int -> ST s Word32
readCellValue vals j = fromIntegral <$> MU.unsafeRead vals j
{-# INLINE readCellValue #-}

writeCellValue :: MU.MVector s Int -> Int -> Word32 -> ST s ()
writeCellValue vals j w = MU.unsafeWrite vals j (heldPattern w)
{-# INLINE writeCellValue #-}

-- | MT-POU-9, MT-LIM-1: at most 16 nested function calls.
maxCallDepth :: Int
maxCallDepth = 16

-- | Reported when the checked program is inconsistent (a value of the wrong
-- type, a missing function): a bug of the checker, never of the ST program.
errMalformed :: ErrorCode
errMalformed = 9999

-- | Record a runtime error: the closures stop at the next check (see
-- 'Meaning'); the value returned is never used.
raise :: Machine s -> RuntimeError -> ST s Value
raise m err = do
  writeSTRef (mError m) err
  MU.unsafeWrite (mCounters m) ixFailed 1
  pure (VBool False)

hasFailed :: Machine s -> ST s Bool
hasFailed m = (/= 0) <$> MU.unsafeRead (mCounters m) ixFailed
{-# INLINE hasFailed #-}

-- | One step of the budget; exceeding it is runtime error 2030 at the line
-- being executed (MT-EXEC-7). FALSE when the budget is exhausted.
tick :: Int -> Line -> Machine s -> ST s Bool
tick budget line m = do
  s <- MU.unsafeRead (mCounters m) ixSteps
  if s >= budget
    then False <$ raise m (runtimeError errExecutionTime line)
    else True <$ MU.unsafeWrite (mCounters m) ixSteps (s + 1)
{-# INLINE tick #-}

--------------------------------------------------------------------------------
-- Variables

-- | The number of elements of a variable (1 for a scalar).
varElements :: Var -> Int
varElements v = case varType v of
  Basic _ -> 1
  Array lo hi _ -> fromInteger (max 0 (hi - lo + 1))

-- | MT-MAP-9: element @k@ of a mapped array lies @k - lower@ operands further
-- (the address for simple operands, the position for table operands).
elementOperand :: Operand -> Int -> Operand
elementOperand op off = case op of
  OpSimple k a -> OpSimple k (a + off)
  OpBit k a b -> OpBit k (a + off) b -- never reached: mapped arrays are not BOOL (MT-MAP-11)
  OpTablePos k a p -> OpTablePos k a (p + off)

-- | A slot of a vector, or the default outside it (never for a checked
-- program: the slots cover every variable).
readSlot :: MV.MVector s Value -> Value -> Int -> ST s Value
readSlot vec def k
  | k >= 0 && k < MV.length vec = MV.unsafeRead vec k
  | otherwise = pure def
{-# INLINE readSlot #-}

-- | Strict in the value: a slot never holds a suspended computation.
writeSlot :: MV.MVector s Value -> Int -> Value -> ST s ()
writeSlot vec k !x
  | k >= 0 && k < MV.length vec = MV.unsafeWrite vec k x
  | otherwise = pure ()
{-# INLINE writeSlot #-}

-- | Read element @off@ (0-based) of a variable; 0 for a scalar. The home
-- is inspected when the closure is built, not when it runs.
readElement :: Var -> Int -> Exec s Value
readElement v off = let r = readRun v off in Exec $ \e m -> Done <$> r e m

-- | A function call's frame (MT-SCOPE-7): a small array, which a call
-- copies from its starting state in one step (no card table, unlike a
-- vector's array).
data CallFrame s = CallFrame (SmallMutableArray# s Value)

newFrame :: Int -> ST s (CallFrame s)
newFrame (I# n) = ST $ \s -> case newSmallArray# n (VBool False) s of
  (# s', a #) -> (# s', CallFrame a #)

-- | A slot of a frame, or the default outside it (never for a checked
-- program: the frame covers every slot of its function).
readFrame :: CallFrame s -> Value -> Int -> ST s Value
readFrame (CallFrame a) def k@(I# k#)
  | k >= 0 && k < I# (sizeofSmallMutableArray# a) = ST (readSmallArray# a k#)
  | otherwise = pure def
{-# INLINE readFrame #-}

writeFrame :: CallFrame s -> Int -> Value -> ST s ()
writeFrame (CallFrame a) k@(I# k#) !x
  | k >= 0 && k < I# (sizeofSmallMutableArray# a) = ST $ \s -> (# writeSmallArray# a k# x s, () #)
  | otherwise = pure ()
{-# INLINE writeFrame #-}

-- | The state a function's frame starts from, immutable.
data FrameStart = FrameStart (SmallArray# Value)

frameStart :: V.Vector Value -> FrameStart
frameStart v = runST $ do
  f@(CallFrame a) <- newFrame (V.length v)
  V.imapM_ (writeFrame f) v
  ST $ \s -> case unsafeFreezeSmallArray# a s of
    (# s', fa #) -> (# s', FrameStart fa #)

-- | A new frame in the starting state.
startFrame :: FrameStart -> ST s (CallFrame s)
startFrame (FrameStart a) = ST $ \s -> case thawSmallArray# a 0# (sizeofSmallArray# a) s of
  (# s', ma #) -> (# s', CallFrame ma #)

-- | A closure over the machine: the form the translated program takes.
type Run s a = Env -> Machine s -> ST s a

readRun :: Var -> Int -> Run s Value
readRun v off = case buildRead v off of Built r -> r

-- | A closure, built. 'readRun' and 'writeRun' take it out of the box of a
-- builder that GHC may not inline: so they have two arguments, and what is
-- computed before the closure's lambda (an operand's cell key) is computed
-- once, not on every run (GHC would otherwise add the closure's arguments
-- to theirs, the work before the lambda looking cheap to it).
data Built a = Built !a

buildRead :: Var -> Int -> Built (Run s Value)
{-# NOINLINE buildRead #-}
buildRead v off = Built $ case varHome v of
  Data i -> let k = i + off in \_ m -> readSlot (mData m) def k
  Frame i -> let k = i + off in \_ m -> readSTRef (mFrame m) >>= \f -> readFrame f def k
  Mapped o -> mappedRead (elementOperand o off) t
  SignalInput n -> \e _ -> pure $! VBool (signal n (envInputs e))
  SignalOutput n -> \_ m -> VBool . (/= 0) <$> MU.unsafeRead (mCounters m) (ixOutput (clampSignal n))
  OverflowFlag -> \_ m -> VBool . (/= 0) <$> MU.unsafeRead (mCounters m) ixOverflow
  where
    t = varBasicType v
    def = defaultValue t

-- | 'readRun' for a translated expression: a mapped variable's slot in the
-- machine's table found now, not on every read.
readRunIn :: Ctx -> Var -> Int -> Run s Value
readRunIn ctx v off = case varHome v of
  Mapped o -> case mappedReadAt (cxCells ctx) (elementOperand o off) (varBasicType v) of Built r -> r
  _ -> readRun v off

writeRunIn :: Ctx -> Var -> Int -> Value -> Run s ()
writeRunIn ctx v off = case varHome v of
  Mapped o -> case mappedWriteAt (cxCells ctx) (elementOperand o off) of Built w -> w
  _ -> writeRun v off

mappedReadAt :: CellSlots -> Operand -> BasicType -> Built (Run s Value)
{-# NOINLINE mappedReadAt #-}
mappedReadAt table o t = case lookupSlot table (cellKey (operandCell o)) of
  j
    | j >= 0 -> case operandReader o t of
        !fromPattern -> Built $ \_ m -> readCellValue (mCells m) j >>= \w -> pure $! fromPattern w
    | otherwise -> Built $ \_ m -> readSTRef (mMemory m) >>= \mem -> pure $! readOperand mem o t

mappedWriteAt :: CellSlots -> Operand -> Built (Value -> Run s ())
{-# NOINLINE mappedWriteAt #-}
mappedWriteAt table o = case lookupSlot table (cellKey (operandCell o)) of
  j
    | j >= 0 -> case operandWriter o of
        !toPattern -> Built $ \x _ m -> readCellValue (mCells m) j >>= \w -> writeCellValue (mCells m) j $! toPattern x w
    | otherwise -> Built $ \x _ m -> modifySTRef' (mMemory m) (writeOperand o x)

-- | The slot of a mapped variable's cell among those the machine holds,
-- when it is a whole cell (not a bit) the table holds; else -1.
heldSlot :: CellSlots -> Operand -> Int
heldSlot table o = case o of
  OpBit {} -> -1
  _ -> lookupSlot table (cellKey (operandCell o))

-- | The typed closure reading a mapped variable of an integer, bit-string
-- or REAL type from its held cell (the pattern's number, no 'Value').
mappedTypedAt :: CellSlots -> Operand -> BasicType -> Typed s
{-# NOINLINE mappedTypedAt #-}
mappedTypedAt table o t = case heldSlot table o of
  j
    | j < 0 -> Untyped
    | intTyped t -> eachPatternNumber t $ \number -> IntTyped (intRun (\_ m -> number <$> readCellValue (mCells m) j))
    | t == REAL -> RealTyped (realRun (\_ m -> realFromBits <$> readCellValue (mCells m) j))
    | otherwise -> Untyped

-- | Read an operand: its cell in the machine's table, else in the memory.
-- The key and the conversion are chosen before the closure is built.
mappedRead :: Operand -> BasicType -> Run s Value
mappedRead o t = case cellKey (operandCell o) of
  !key -> case operandReader o t of
    !fromPattern -> \_ m -> case lookupSlot (mCellSlots m) key of
      j
        | j >= 0 -> readCellValue (mCells m) j >>= \w -> pure $! fromPattern w
        | otherwise -> readSTRef (mMemory m) >>= \mem -> pure $! readOperand mem o t

-- | Write an operand (a bit: only its bit), as 'mappedRead'.
mappedWrite :: Operand -> Value -> Run s ()
mappedWrite o = case cellKey (operandCell o) of
  !key -> case operandWriter o of
    !toPattern -> \x _ m -> case lookupSlot (mCellSlots m) key of
      j
        | j >= 0 -> readCellValue (mCells m) j >>= \w -> writeCellValue (mCells m) j $! toPattern x w
        | otherwise -> modifySTRef' (mMemory m) (writeOperand o x)

-- | OUTPUT1..3 only (the checker knows no others).
clampSignal :: Int -> Int
clampSignal n = max 1 (min 3 n)

signal :: Int -> (Bool, Bool, Bool) -> Bool
signal n (a, b, c) = case n of
  1 -> a
  2 -> b
  3 -> c
  _ -> False

readScalar :: Var -> Exec s Value
readScalar v = readElement v 0

-- | Write element @off@ of a variable. INPUTn are read-only (MT-SIG-2); the
-- checker never produces such a write, and it is ignored here.
writeElement :: Var -> Int -> Value -> Exec s ()
writeElement v off = let w = writeRun v off in \x -> Exec $ \e m -> Done <$> w x e m

writeRun :: Var -> Int -> Value -> Run s ()
writeRun v off = case buildWrite v off of Built w -> w

buildWrite :: Var -> Int -> Built (Value -> Run s ())
{-# NOINLINE buildWrite #-}
buildWrite v off = Built $ case varHome v of
  Data i -> let k = i + off in \x _ m -> writeSlot (mData m) k x
  Frame i -> let k = i + off in \x _ m -> readSTRef (mFrame m) >>= \f -> writeFrame f k x
  Mapped o -> mappedWrite (elementOperand o off)
  SignalInput _ -> \_ _ _ -> pure ()
  SignalOutput n
    | n >= 1 && n <= 3 -> \x _ m -> MU.unsafeWrite (mCounters m) (ixOutput n) (fromEnum (boolOf x))
    | otherwise -> \_ _ _ -> pure ()
  OverflowFlag -> \x _ m -> MU.unsafeWrite (mCounters m) ixOverflow (fromEnum (boolOf x))
  where
    boolOf = \case
      VBool b -> b
      _ -> False

writeScalar :: Var -> Value -> Exec s ()
writeScalar v = writeElement v 0

-- | Give a variable its initial value (MT-VAR-3, MT-VAR-4, MT-ARR-6): the
-- initialiser, or the type default; a mapped variable without initialiser
-- is left alone (MT-VAR-3, MT-MAP-4 b), one with an initialiser is written
-- (decision A3, MT-MAP-15).
initVar :: VarInit -> Exec s ()
initVar (VarInit v ini) = case (varHome v, ini) of
  (Mapped _, Nothing) -> pure ()
  (_, Nothing) -> mapM_ (\k -> writeElement v k def) [0 .. varElements v - 1]
  (_, Just (InitScalar x)) -> mapM_ (\k -> writeElement v k x) [0 .. varElements v - 1]
  (_, Just (InitArray xs)) -> mapM_ (uncurry (writeElement v)) (zip [0 .. varElements v - 1] xs)
  where
    def = defaultValue (varBasicType v)

-- | The type defaults of the slots of a vector (data area or frame): every
-- slot of every given variable with the given home, the rest FALSE.
slotDefaults :: (Home -> Maybe Int) -> Int -> [Var] -> V.Vector Value
slotDefaults base size vars =
  V.replicate (max size top) (VBool False)
    V.// [ (i + k, defaultValue (varBasicType v))
         | v <- vars
         , Just i <- [base (varHome v)]
         , k <- [0 .. varElements v - 1]
         ]
  where
    top = maximum (0 : [i + varElements v | v <- vars, Just i <- [base (varHome v)]])

--------------------------------------------------------------------------------
-- Translation

-- | How a statement ends: on to the next one, leaving the innermost loop
-- (EXIT, MT-STMT-12), leaving the function or program (RETURN, MT-STMT-4,
-- MT-STMT-5), or stopped by a runtime error (in 'mError', MT-EXEC-8).
data Flow = Next | Exiting | Returning | Failing
  deriving (Eq, Show)

-- | A translated module: the program body and the functions, each a
-- closure.
data CompiledModule = CompiledModule
  { cmBody :: forall s. Exec s Flow
  , cmFunctionMeanings :: IntMap Function
  , cmDataDefaults :: V.Vector Value -- ^ the initial data area: every slot at its type default
  , cmCellSlots :: CellSlots
  -- ^ the table of the cells a machine for this module holds ('newMachine'
  -- is given it): an operand's slot in it is found when the closure is built
  , cmTraced :: Bool -- ^ translated by 'compileTracedModule'
  }

-- | The meaning of a function: arguments to result.
data Function = Function
  { fnName :: Text
  , fnFrame :: FrameStart
  -- ^ the frame a call starts from (MT-SCOPE-7): the result at its type
  -- default, the locals kept in the frame at their initial values, the
  -- rest at their type defaults until the arguments are written
  , fnParams :: [Var] -- ^ the parameters in declaration order (MT-POU-5)
  , fnRun :: forall s. Run s Value -- ^ the call, once its frame is installed
  }

data Ctx = Ctx
  { cxPolicies :: Policies
  , cxFunctions :: IntMap Function
  , cxCells :: CellSlots -- ^ the machine's table of held cells ('cmCellSlots')
  , cxTrace :: Bool -- ^ build the traced closures (section "Tracing")
  , cxLine :: Line -- ^ when tracing: the line of the statement being translated, where its reads happen
  }

-- | The meaning of an expression: a closure giving its value, and whether
-- it can fail. After a closure that can fail, the caller looks at the
-- machine's error flag before it goes on, so an error stops the evaluation
-- at once (no later operand is evaluated, no later write happens).
--
-- The 'Leaf' says when the expression is a constant or a variable in a slot,
-- so that an operator over it reads the slot itself instead of calling a
-- closure (the most common operands; a call per leaf would dominate).
data Meaning s = Meaning !Bool !(Run s Value) !Leaf !(Typed s)

data Leaf
  = Constant !Value
  | DataSlot !Int !Value -- ^ a slot of the data area, and the type default
  | FrameSlot !Int !Value -- ^ a slot of the active frame, and the type default
  | Computed

-- | A closure built by a step of translation. The strict box keeps GHC
-- from moving the choices made while building it (which leaf, which
-- operator) into the closure, where they would be made again on every run.
data Staged s = Staged !(Run s Value)

-- | An expression that is none of the leaves.
computed :: Bool -> Run s Value -> Meaning s
computed canFail r = Meaning canFail r Computed Untyped

staged :: Bool -> Staged s -> Meaning s
staged canFail (Staged r) = computed canFail r

-- | Give the continuation a closure reading the operand: for a leaf, a
-- closure that does the read itself (inlined there), else the operand's
-- closure.
withOperand :: Meaning s -> (Run s Value -> r) -> r
withOperand (Meaning _ r leaf _) k = case leaf of
  Constant c -> k (\_ _ -> pure c)
  DataSlot i d -> k (\_ m -> readSlot (mData m) d i)
  FrameSlot i d -> k (\_ m -> readSTRef (mFrame m) >>= \f -> readFrame f d i)
  Computed -> k r
{-# INLINE withOperand #-}

--------------------------------------------------------------------------------
-- Typed closures

-- | A closure giving the number of an expression of an integer or bit-string
-- type ('intTyped'), returned unboxed: an operator over such closures
-- allocates nothing, where a 'Value' would be built and taken apart at every
-- node of the expression.
type IntRun s = Env -> Machine s -> State# s -> (# State# s, Int# #)

-- | An 'IntRun' written in 'ST' (inlined: the 'Int' is never built).
intRun :: (Env -> Machine s -> ST s Int) -> IntRun s
intRun f = \e m s -> case f e m of ST g -> case g s of (# s', I# n #) -> (# s', n #)
{-# INLINE intRun #-}

runInt :: IntRun s -> Env -> Machine s -> ST s Int
runInt r e m = ST (\s -> case r e m s of (# s', n #) -> (# s', I# n #))
{-# INLINE runInt #-}

-- | A closure giving the binary32 value of a REAL expression unboxed.
type RealRun s = Env -> Machine s -> State# s -> (# State# s, Float# #)

realRun :: (Env -> Machine s -> ST s Float) -> RealRun s
realRun f = \e m s -> case f e m of ST g -> case g s of (# s', F# x #) -> (# s', x #)
{-# INLINE realRun #-}

runReal :: RealRun s -> Env -> Machine s -> ST s Float
runReal r e m = ST (\s -> case r e m s of (# s', x #) -> (# s', F# x #))
{-# INLINE runReal #-}

-- | The typed form of an expression, when it has one.
data Typed s
  = Untyped
  | IntTyped !(IntRun s)
  | IntOfLeaf !Leaf -- ^ the number of a leaf of another integer type (a widening conversion of a variable)
  | RealTyped !(RealRun s)

data StagedReal s = StagedReal !(RealRun s)

-- | The binary32 value of a REAL value (the checker gives each expression
-- one type, so nothing else comes here).
realOf :: Value -> Float
realOf = \case
  VReal x -> x
  _ -> 0
{-# INLINE realOf #-}

-- | A REAL expression given by its typed closure.
realMeaning :: Bool -> StagedReal s -> Meaning s
realMeaning canFail (StagedReal r) = case Staged (\e m -> runReal r e m >>= \x -> pure $! VReal x) of
  Staged g -> Meaning canFail g Computed (RealTyped r)

-- | A typed closure built by a step of translation (see 'Staged').
data StagedInt s = StagedInt !(IntRun s)

-- | The types whose values the typed closures carry as a machine 'Int' (all
-- at most 32 bits wide).
intTyped :: BasicType -> Bool
intTyped t = t `elem` [INT, DINT, USINT, BYTE, WORD, DWORD]

-- | The number of a value of an 'intTyped' type (the checker gives each
-- expression one type, so a REAL never comes here).
numberOf :: Value -> Int
numberOf v = case valueToInt v of
  Just n -> n
  Nothing -> 0
{-# INLINE numberOf #-}

-- | An expression of an 'intTyped' type given by its typed closure; its
-- 'Value' closure boxes the number as the type's value.
intMeaning :: Bool -> BasicType -> StagedInt s -> Meaning s
intMeaning canFail t (StagedInt r) = case boxed t r of
  Staged g -> Meaning canFail g Computed (IntTyped r)

-- | The value of a typed closure's number, the type chosen once.
boxed :: BasicType -> IntRun s -> Staged s
boxed t r = eachIntBox t box
  where
    box mk = Staged $ \e m -> runInt r e m >>= \n -> pure $! mk n
    {-# INLINE box #-}

-- | The typed closure of an operand of an 'intTyped' type: a leaf read
-- directly, a typed closure as it is, any other closure's value taken apart.
intRunOf :: Meaning s -> IntRun s
intRunOf (Meaning _ r leaf typed) = case (leaf, typed) of
  (Computed, IntTyped ir) -> ir
  (Computed, IntOfLeaf l) -> ofLeaf l
  (l, _) -> ofLeaf l
  where
    ofLeaf = \case
      Constant c -> case numberOf c of I# n -> \_ _ s -> (# s, n #)
      DataSlot i d -> intRun (\_ m -> numberOf <$> readSlot (mData m) d i)
      FrameSlot i d -> intRun (\_ m -> readSTRef (mFrame m) >>= \f -> numberOf <$> readFrame f d i)
      Computed -> intRun (\e m -> numberOf <$> r e m)
-- never inlined: the choice of leaf must be made once, when the closure
-- over it is built, not inside that closure on every run
{-# NOINLINE intRunOf #-}

-- | 'intRunOf' for a REAL operand.
realRunOf :: Meaning s -> RealRun s
realRunOf (Meaning _ r leaf typed) = case leaf of
  Constant c -> case realOf c of F# x -> \_ _ s -> (# s, x #)
  DataSlot i d -> realRun (\_ m -> realOf <$> readSlot (mData m) d i)
  FrameSlot i d -> realRun (\_ m -> readSTRef (mFrame m) >>= \f -> realOf <$> readFrame f d i)
  Computed -> case typed of
    RealTyped rr -> rr
    _ -> realRun (\e m -> realOf <$> r e m)
{-# NOINLINE realRunOf #-}

-- | Two operands left to right (decision A18), stopping at an error (then
-- @failed@ is the result, never used), else @f@ on their values.
twoOperands :: Bool -> (Env -> Machine s -> ST s x) -> Bool -> (Env -> Machine s -> ST s y) -> a -> (x -> y -> Machine s -> ST s a) -> Env -> Machine s -> ST s a
twoOperands fa ra fb rb failed f = \e m -> do
  x <- ra e m
  bad <- if fa then hasFailed m else pure False
  if bad
    then pure failed
    else do
      y <- rb e m
      bad' <- if fb then hasFailed m else pure False
      if bad' then pure failed else f x y m
{-# INLINE twoOperands #-}

oneOperand :: Bool -> (Env -> Machine s -> ST s x) -> a -> (x -> Machine s -> ST s a) -> Env -> Machine s -> ST s a
oneOperand fa ra failed f = \e m -> do
  x <- ra e m
  bad <- if fa then hasFailed m else pure False
  if bad then pure failed else f x m
{-# INLINE oneOperand #-}

-- | 'twoOperands' on the numbers of two operands of an 'intTyped' type;
-- @wrap@ receives the closure. Inlined where @f@ and @wrap@ are known: one
-- closure per operator, with the operator's code in it, the operands'
-- closures chosen before it is built.
intBinary :: Meaning s -> Meaning s -> a -> (Int -> Int -> Machine s -> ST s a) -> ((Env -> Machine s -> ST s a) -> b) -> b
intBinary ma mb failed f wrap = case (ma, mb) of
  -- the commonest operands are part of the closure: a variable of the data
  -- area on the left (n + 1, acc + x), a constant on the right (i * 7, n MOD 16)
  (Meaning _ _ (DataSlot i d) _, Meaning _ _ (Constant c) _) -> case numberOf c of
    !y -> wrap (\_ m -> readSlot (mData m) d i >>= \v -> f (numberOf v) y m)
  (Meaning _ _ (DataSlot i d) _, _) -> case intRunOf mb of
    !rb -> wrap (twoOperands False (\_ m -> numberOf <$> readSlot (mData m) d i) (failsM mb) (runInt rb) failed f)
  (_, Meaning _ _ (Constant c) _) -> case (intRunOf ma, numberOf c) of
    (!ra, !y) -> wrap (oneOperand (failsM ma) (runInt ra) failed (\x m -> f x y m))
  _ -> case (intRunOf ma, intRunOf mb) of
    (!ra, !rb) -> wrap (twoOperands (failsM ma) (runInt ra) (failsM mb) (runInt rb) failed f)
{-# INLINE intBinary #-}

intUnary :: Meaning s -> a -> (Int -> Machine s -> ST s a) -> ((Env -> Machine s -> ST s a) -> b) -> b
intUnary ma failed f wrap = case intRunOf ma of
  !ra -> wrap (oneOperand (failsM ma) (runInt ra) failed f)
{-# INLINE intUnary #-}

-- | 'intBinary' for REAL operands.
realBinary :: Meaning s -> Meaning s -> a -> (Float -> Float -> Machine s -> ST s a) -> ((Env -> Machine s -> ST s a) -> b) -> b
realBinary ma mb failed f wrap = case (realRunOf ma, realRunOf mb) of
  (!ra, !rb) -> wrap (twoOperands (failsM ma) (runReal ra) (failsM mb) (runReal rb) failed f)
{-# INLINE realBinary #-}

realUnary :: Meaning s -> a -> (Float -> Machine s -> ST s a) -> ((Env -> Machine s -> ST s a) -> b) -> b
realUnary ma failed f wrap = case realRunOf ma of
  !ra -> wrap (oneOperand (failsM ma) (runReal ra) failed f)
{-# INLINE realUnary #-}

-- | The wrappers for the typed closures.
typedInt :: (Env -> Machine s -> ST s Int) -> StagedInt s
typedInt r = StagedInt (intRun r)
{-# INLINE typedInt #-}

typedReal :: (Env -> Machine s -> ST s Float) -> StagedReal s
typedReal r = StagedReal (realRun r)
{-# INLINE typedReal #-}

failsM :: Meaning s -> Bool
failsM (Meaning f _ _ _) = f

-- | Translate the whole module once. Functions refer to each other through
-- the lazily built table of meanings (a knot: each function is translated
-- once, however often it is called).
compileModule :: Policies -> CellSlots -> CModule -> CompiledModule
compileModule = translateModule False

-- | 'compileModule' with tracing on: the closures emit 'Event's into the
-- machine's tracer ('mTrace') as they run.
compileTracedModule :: Policies -> CellSlots -> CModule -> CompiledModule
compileTracedModule = translateModule True

translateModule :: Bool -> Policies -> CellSlots -> CModule -> CompiledModule
translateModule tracing pol table cm = CompiledModule (flowExec (compileBlock ctx (cpBody prog))) funs defaults table tracing
  where
    ctx = Ctx pol funs table tracing 0
    funs = IM.map (compileFunction ctx) (cmFunctions cm)
    prog = cmProgram cm
    defaults =
      slotDefaults dataSlot (cmDataSize cm) $
        map viVar (cmInits cm) ++ cpInputs prog ++ cpInOuts prog ++ cpOutputs prog ++ map snd (cmNamed cm)
    dataSlot = \case
      Data i -> Just i
      _ -> Nothing

-- | A statement closure as an 'Exec': 'Failing' becomes the error.
flowExec :: Run s Flow -> Exec s Flow
flowExec r = Exec $ \e m ->
  r e m >>= \case
    Failing -> Failed <$> readSTRef (mError m)
    fl -> pure (Done fl)

-- | An expression closure as an 'Exec'.
compileExpr :: Ctx -> CExpr -> Exec s Value
compileExpr ctx x =
  let Meaning _ r _ _ = meaning ctx x
   in Exec $ \e m -> do
        v <- r e m
        bad <- hasFailed m
        if bad then Failed <$> readSTRef (mError m) else pure (Done v)

-- | A function call in a fresh frame (MT-SCOPE-7): the result slot starts
-- at its type default, the parameters take the arguments in declaration
-- order (MT-POU-5), the locals their initial values; the result is the
-- result slot when the body ends or returns (MT-POU-4, MT-STMT-4). The
-- locals' initial values are constants, so they are part of the frame a
-- call starts from; a local whose home is not in the frame is initialised
-- on each call.
compileFunction :: Ctx -> CFunction -> Function
compileFunction ctx f = Function (cfName f) template (cfParams f) run
  where
    run :: Run s Value
    run e m = do
      r <- unExec initElsewhere e m
      case r of
        Failed err -> raise m err
        Done () ->
          body e m >>= \case
            Failing -> pure (VBool False)
            _ -> readSTRef (mFrame m) >>= \fr -> readFrame fr result 0
    body = compileBlock ctx (cfBody f)
    (inFrame, elsewhere) = partition (isFrame . varHome . viVar) (cfLocals f)
    initElsewhere = mapM_ initVar elsewhere
    isFrame = \case
      Frame _ -> True
      _ -> False
    result = defaultValue (cfResult f)
    frameSlot = \case
      Frame i -> Just i
      _ -> Nothing
    -- slot 0 is the result, at its default; the locals at their initial
    -- values (MT-VAR-3, MT-VAR-4, MT-ARR-6, as 'initVar' writes them); the
    -- others at their types' defaults until written
    template =
      frameStart $
        slotDefaults frameSlot (cfFrameSize f) (cfParams f ++ map viVar (cfLocals f))
          V.// ((0, result) : concatMap initial inFrame)
    initial (VarInit v ini) = case (varHome v, ini) of
      (Frame i, Just (InitScalar x)) -> [(i + k, x) | k <- [0 .. varElements v - 1]]
      (Frame i, Just (InitArray xs)) -> zip [i + k | k <- [0 .. varElements v - 1]] xs
      _ -> []

-- | A statement list: stops at the first EXIT, RETURN or error.
compileBlock :: Ctx -> [CStmt] -> Run s Flow
compileBlock ctx = go . map (compileStmt ctx)
  where
    go [] = \_ _ -> pure Next
    go [s] = s
    go (s : ss) =
      let !rest = go ss
       in \e m ->
            s e m >>= \case
              Next -> rest e m
              other -> pure other

-- | Run an expression, then the continuation with its value, unless the
-- expression failed.
withValue :: Meaning s -> Env -> Machine s -> (Value -> ST s Flow) -> ST s Flow
withValue (Meaning canFail r _ _) e m k
  | canFail = do
      x <- r e m
      bad <- hasFailed m
      if bad then pure Failing else k x
  | otherwise = r e m >>= k
{-# INLINE withValue #-}

-- | Evaluate two operands left to right (decision A18), stopping at an
-- error, then combine them.
binary :: Meaning s -> Meaning s -> (Machine s -> Value -> Value -> ST s Value) -> Bool -> Meaning s
binary ma@(Meaning fa _ _ _) mb@(Meaning fb _ _ _) f canFail =
  case withOperand ma $ \ra -> withOperand mb $ \rb -> Staged $ \e m -> do
      x <- ra e m
      bad <- if fa then hasFailed m else pure False
      if bad
        then pure x
        else do
          y <- rb e m
          bad' <- if fb then hasFailed m else pure False
          if bad' then pure y else f m x y
  of
    Staged r -> computed (fa || fb || canFail) r
{-# INLINE binary #-}

unary :: Meaning s -> (Machine s -> Value -> ST s Value) -> Bool -> Meaning s
unary ma@(Meaning fa _ _ _) f canFail =
  case withOperand ma $ \ra -> Staged $ \e m -> do
    x <- ra e m
    bad <- if fa then hasFailed m else pure False
    if bad then pure x else f m x
  of
    Staged r -> computed (fa || canFail) r
{-# INLINE unary #-}

-- | Apply an operator's result: a runtime error at the node's line, or the
-- value with its effect on INTERNAL_OVERFLOW (MT-OP-7).
result :: Line -> Machine s -> Result -> ST s Value
result line m = \case
  Flagged v o -> v <$ MU.unsafeWrite (mCounters m) ixOverflow (fromEnum o)
  Plain v -> pure v
  Raised code -> raise m (runtimeError code line)
{-# INLINE result #-}

-- | 'result' for the reference operators' 'O.Outcome'.
outcome :: Line -> Machine s -> O.Outcome -> ST s Value
outcome line m = result line m . fromOutcome
{-# INLINE outcome #-}

malformed :: Line -> Machine s -> ST s Value
malformed line m = raise m (runtimeError errMalformed line)

-- | The 0-based element of an array for an index value, under the
-- @index-out-of-range@ policy (MT-ARR-2, MT-ARR-8, decision A23); a
-- negative number after an error was raised.
elementIndex :: Policies -> Line -> Var -> Machine s -> Value -> ST s Int
elementIndex pol line v = case intBounds v of
  Just (loI, hiI) -> \m iv -> case valueToInt iv of
    Just k
      | k >= loI && k <= hiI -> pure (k - loI)
    _ -> elementIndexRef pol line v m iv
  Nothing -> elementIndexRef pol line v

-- | The bounds of an array as machine integers, when both fit a DINT (the
-- common case, handled without 'Integer').
intBounds :: Var -> Maybe (Int, Int)
intBounds v = case varType v of
  Array lo hi _
    | lo >= toInteger (minBound :: Int32) && hi <= toInteger (maxBound :: Int32) ->
        Just (fromInteger lo, fromInteger hi)
  _ -> Nothing

elementIndexRef :: Policies -> Line -> Var -> Machine s -> Value -> ST s Int
elementIndexRef pol line v m iv = case valueToInteger iv of
  Nothing -> (-1) <$ raise m (runtimeError errMalformed line)
  Just k -> indexNumber pol line v m k

-- | 'elementIndex' for the number of the index.
indexNumber :: Policies -> Line -> Var -> Machine s -> Integer -> ST s Int
indexNumber pol line v m k = case varType v of
  Basic _ -> failed errMalformed
  Array lo hi _
    | k >= lo && k <= hi -> pure (fromInteger (k - lo))
    | otherwise -> case pIndexOutOfRange pol of
        IndexError -> failed errIndex -- MT-ERR-2015
        IndexTrap -> failed trapIndex
        IndexClamp -> pure (fromInteger (max lo (min hi k) - lo))
  where
    failed c = (-1) <$ raise m (runtimeError c line)

-- | An index is a DINT expression (MT-ARR-2); the conversion of a narrower
-- integer to DINT keeps its number, which is all an index needs, so it is
-- left out ('elementIndex' takes any integer value).
indexExpr :: CExpr -> CExpr
indexExpr = \case
  CConv from DINT x | from `elem` [INT, USINT, BYTE, WORD] -> x
  x -> x

-- | TRUE and FALSE without allocating a value.
boolValue :: Bool -> Value
boolValue b = if b then VBool True else VBool False
{-# INLINE boolValue #-}

-- | The meaning of an expression: the fast closures, or with tracing on
-- the traced ones.
meaning :: Ctx -> CExpr -> Meaning s
meaning ctx
  | cxTrace ctx = tracedMeaning ctx
  | otherwise = fastMeaning ctx

fastMeaning :: Ctx -> CExpr -> Meaning s
fastMeaning ctx = \case
  CLit v -> Meaning False (\_ _ -> pure v) (Constant v) Untyped
  CRead v ->
    let leaf = case varHome v of
          Data i -> DataSlot i (defaultValue (varBasicType v))
          Frame i -> FrameSlot i (defaultValue (varBasicType v))
          _ -> Computed
        typed = case varHome v of
          Mapped o -> mappedTypedAt (cxCells ctx) o (varBasicType v)
          _ -> Untyped
     in Meaning False (readRunIn ctx v 0) leaf typed
  CReadIndex line v ix ->
    let index = elementIndex pol line v
        -- the element closures, built once
        elements = V.generate (varElements v) (readRunIn ctx v)
        def = defaultValue (varBasicType v)
        ix' = indexExpr ix
        ixM@(Meaning fi _ _ _) = meaning ctx ix'
        -- the index, unless it failed
        withIndex ri e m k = do
          iv <- ri e m
          bad <- if fi then hasFailed m else pure False
          if bad then pure iv else k iv
        {-# INLINE withIndex #-}
     in case (varHome v, intBounds v) of
          (Data base, Just (lo, hi))
            | intTyped (cexprType ix') ->
                -- an element of the data area: the index as a number, the
                -- bounds checked inline
                let element i m
                      | i >= lo && i <= hi = readSlot (mData m) def (base + i - lo)
                      | otherwise = indexNumber pol line v m (toInteger i) >>= \k -> if k < 0 then pure def else readSlot (mData m) def (base + k)
                    {-# INLINE element #-}
                    -- an index that is a variable of the data area is read
                    -- in the closure (V[I]), else its closure is called
                    indexSlot = case ixM of
                      Meaning _ _ (DataSlot j d') _ -> Just (j, d')
                      _ -> Nothing
                    typed
                      | intTyped (varBasicType v) = case indexSlot of
                          Just (j, d') -> IntTyped (intRun (\_ m -> readSlot (mData m) d' j >>= \iv -> numberOf <$> element (numberOf iv) m))
                          Nothing -> case intUnary ixM 0 (\i m -> numberOf <$> element i m) typedInt of
                            StagedInt r -> IntTyped r
                      | varBasicType v == REAL = case indexSlot of
                          Just (j, d') -> RealTyped (realRun (\_ m -> readSlot (mData m) d' j >>= \iv -> realOf <$> element (numberOf iv) m))
                          Nothing -> case intUnary ixM 0 (\i m -> realOf <$> element i m) typedReal of
                            StagedReal r -> RealTyped r
                      | otherwise = Untyped
                    generic = case indexSlot of
                      Just (j, d') -> Staged (\_ m -> readSlot (mData m) d' j >>= \iv -> element (numberOf iv) m)
                      Nothing -> intUnary ixM def element Staged
                 in case generic of
                      Staged r -> Meaning True r Computed typed
          _ -> staged True $ withOperand ixM $ \ri -> Staged $ \e m -> withIndex ri e m $ \iv ->
            index m iv >>= \k ->
              if k < 0
                then pure iv
                else maybe (malformed line m) (\r -> r e m) (elements V.!? k)
  CConv from to x
    | Just m <- intConversion ctx from to x -> m
    | to == REAL && from `elem` [INT, USINT] ->
        -- exact: every INT and USINT is a binary32 (MT-CONV-5)
        let xM = meaning ctx x
         in realMeaning (failsM xM) (intUnary xM 0 (\n _ -> pure $! fromIntegral n) typedReal)
    | otherwise -> case convertFast pol from to of
        Unary conv -> unary (meaning ctx x) (\_ v -> pure $! conv v) False -- MT-CONV-5
  CNeg line _ x -> unary (meaning ctx x) (\m v -> outcome line m (O.negateValue pol v)) True -- MT-OP-4, MT-OP-6
  CNot _ x -> unary (meaning ctx x) (\_ v -> pure $! O.notValue v) False -- MT-OP-14
  CArith line op t a b
    | t `elem` [INT, DINT, USINT] ->
        -- MT-OP-4..10 on numbers, the outcome written straight to the machine
        let ma = meaning ctx a
            mb = meaning ctx b
            canFail = failsM ma || failsM mb || arithCanFail pol op t
            flagged m n o = (pure $! n) <* MU.unsafeWrite (mCounters m) ixOverflow (fromEnum o) -- MT-OP-7
            plain n = pure $! n
            raised m c = 0 <$ raise m (runtimeError c line)
            !ia = intArith pol t
            on o =
              -- named and inlined: intBinary uses it in each of its cases,
              -- and a shared function would box its result
              let apply x y m = intOp (flagged m) plain (raised m) ia o x y
                  {-# INLINE apply #-}
               in intMeaning canFail t (intBinary ma mb 0 apply typedInt)
            {-# INLINE on #-}
         in eachArithOp on op
  CArith line op REAL a b ->
    -- MT-OP-4, A6 on binary32 values
    let ma = meaning ctx a
        mb = meaning ctx b
        canFail = failsM ma || failsM mb || arithCanFail pol op REAL
        flagged m x o = (pure $! x) <* MU.unsafeWrite (mCounters m) ixOverflow (fromEnum o) -- MT-OP-7
        plain x = pure $! x
        raised m c = 0 <$ raise m (runtimeError c line)
        on o = realMeaning canFail (realBinary ma mb 0 (\x y m -> O.realArithWith (flagged m) plain (raised m) pol o x y) typedReal)
        {-# INLINE on #-}
     in eachArithOp on op
  CArith line op t a b -> case arithFast pol op t of
    Binary f -> binary (meaning ctx a) (meaning ctx b) (\m x y -> result line m (f x y)) True
  CCompare op t a b
    | intTyped t ->
        -- MT-OP-11 on numbers
        let ma = meaning ctx a
            mb = meaning ctx b
            on o = case intBinary ma mb (VBool False) (\x y _ -> pure $! boolValue (cmpWith o x y)) Staged of
              Staged r -> computed (failsM ma || failsM mb) r
            {-# INLINE on #-}
         in eachCmpOp on op
  CCompare op REAL a b ->
    -- MT-OP-11 in IEEE order
    let ma = meaning ctx a
        mb = meaning ctx b
        on o = case realBinary ma mb (VBool False) (\x y _ -> pure $! boolValue (cmpWith o x y)) Staged of
          Staged r -> computed (failsM ma || failsM mb) r
        {-# INLINE on #-}
     in eachCmpOp on op
  CCompare op _ a b -> case compareFast op of
    Binary f -> binary (meaning ctx a) (meaning ctx b) (\_ x y -> pure $! boolValue (f x y)) False
  CLogic op t a b
    | t `elem` [BYTE, WORD, DWORD] ->
        -- MT-OP-12..14 bit by bit on the numbers (both below 2^32)
        let ma = meaning ctx a
            mb = meaning ctx b
            on f = intMeaning (failsM ma || failsM mb) t (intBinary ma mb 0 (\x y _ -> pure $! f x y) typedInt)
            {-# INLINE on #-}
         in case op of
              OpAnd -> on (.&.)
              OpOr -> on (.|.)
              OpXor -> on xor
  CLogic op t a b ->
    let eager = binary (meaning ctx a) (meaning ctx b) (\_ x y -> pure $! O.logic op x y) False
     in case (pShortCircuit pol, t, op) of
          -- decision A17: eager by default; the short-circuit alternative skips
          -- the right operand of AND/OR on BOOL when the left one decides
          (ShortCircuit, BOOL, OpAnd) -> shortCircuit (VBool False)
          (ShortCircuit, BOOL, OpOr) -> shortCircuit (VBool True)
          _ -> eager
    where
      shortCircuit decisive =
        let Meaning fa ra _ _ = meaning ctx a
            Meaning fb rb _ _ = meaning ctx b
         in computed (fa || fb) $ \e m -> do
              x <- ra e m
              bad <- if fa then hasFailed m else pure False
              if bad || x == decisive
                then pure x
                else do
                  y <- rb e m
                  bad' <- if fb then hasFailed m else pure False
                  if bad' then pure y else pure $! O.logic op x y
  CCall line fid _ args -> computed True (compileCall ctx line fid args)
  CExpt line _ a b -> binary (meaning ctx a) (meaning ctx b) (\m x y -> outcome line m (O.expt pol x y)) True -- MT-OP-20
  where
    pol = cxPolicies ctx

-- | The conversions (MT-CONV-5, Table 4-6) to an 'intTyped' type that have a
-- typed closure: those keeping the number, the narrowing of a DINT under
-- either @narrow-int@ alternative, and REAL to DINT or INT under the
-- saturating @real-to-int@ alternatives (as "Stref.Eval.Fast" does on values;
-- NaN, infinities and magnitudes from 2^31 go to the reference).
intConversion :: Ctx -> BasicType -> BasicType -> CExpr -> Maybe (Meaning s)
intConversion ctx from to x = case (from, to) of
  (INT, DINT) -> same
  (USINT, INT) -> same
  (USINT, DINT) -> same
  (BYTE, WORD) -> same
  (BYTE, DWORD) -> same
  (WORD, DWORD) -> same
  (DINT, INT) -> narrowing
  (DINT, BYTE) -> narrowing
  (DINT, WORD) -> narrowing
  (REAL, DINT) -> fromReal
  (REAL, INT) -> fromReal
  _ -> Nothing
  where
    pol = cxPolicies ctx
    xM = meaning ctx x
    onNumber f = Just $ intMeaning (failsM xM) to $ case xM of
      -- a variable of the data area is read in the closure
      Meaning _ _ (DataSlot i d) _ -> typedInt (\_ m -> readSlot (mData m) d i >>= \v -> pure $! f (numberOf v))
      _ -> intUnary xM 0 (\n _ -> pure $! f n) typedInt
    {-# INLINE onNumber #-}
    -- the number unchanged: a variable is read as it is
    same = case xM of
      Meaning canFail _ leaf _
        | isSlot leaf -> case onNumber id of
            Just (Meaning _ g _ _) -> Just (Meaning canFail g Computed (IntOfLeaf leaf))
            Nothing -> Nothing
      _ -> onNumber id
    isSlot = \case
      DataSlot {} -> True
      FrameSlot {} -> True
      _ -> False
    (lo, hi) = range to
    -- C16, C17, C44-C47: the low bits, or the nearest value
    narrowing = case (pNarrowInt pol, to) of
      (NarrowSaturate, _) -> onNumber (\n -> max lo (min hi n))
      (NarrowWrap, INT) -> onNumber (\n -> fromIntegral (fromIntegral n :: Int16))
      (NarrowWrap, _) -> onNumber (.&. hi)
    -- C52, C53 (see 'convertFast')
    fromReal = case pRealToInt pol of
      TruncateSaturate -> onReal (\r -> max lo (min hi (truncate r)))
      RoundEvenSaturate -> onReal (\r -> max lo (min hi (round r)))
      RoundEvenWrap -> Nothing
    reference = convert pol from to
    onReal f =
      let toNumber = \case
            VReal r | abs r < 2147483648 -> f r
            v -> numberOf (reference v)
          {-# INLINE toNumber #-}
       in Just (intMeaning (failsM xM) to (realUnary xM 0 (\r _ -> pure $! toNumber (VReal r)) typedInt))
    {-# INLINE onReal #-}

-- | A call: arguments left to right (decision A18), then the body in a new
-- frame ('inFrame').
compileCall :: Ctx -> Line -> FunId -> [CExpr] -> Run s Value
compileCall ctx line fid args = case IM.lookup fid (cxFunctions ctx) of
  Nothing -> \_ m -> malformed line m
  Just fn -> \e m -> do
    fr <- startFrame (fnFrame fn)
    later <- passArguments fr argsM e m
    bad <- hasFailed m
    if bad
      then pure (VBool False)
      else inFrame line fn fr later e m
    where
      argsM = zip (fnParams fn) (map (meaning ctx) args)

-- | The body of a function whose arguments are passed ('passArguments'
-- gave @later@) in the frame @fr@, one level deeper; a 17th nested frame is
-- runtime error 2050 at the line of the call (MT-POU-9, decision A27). The
-- caller's frame comes back afterwards.
inFrame :: Line -> Function -> CallFrame s -> [Run s ()] -> Run s Value
inFrame line fn fr later e m
  | envDepth e >= maxCallDepth = raise m (runtimeError errCallDepth line) -- MT-ERR-2050
  | otherwise = do
      saved <- readSTRef (mFrame m)
      writeSTRef (mFrame m) fr
      let e' = e {envDepth = envDepth e + 1}
      mapM_ (\w -> w e' m) later
      r <- fnRun fn e' m
      writeSTRef (mFrame m) saved
      pure r
-- inlined, like 'passArguments', into the call's closure: the frame stays
-- unboxed there (filter: 0.6% more instructions when both were shared calls)
{-# INLINE inFrame #-}

-- | The arguments left to right, stopping at the first error: one for a
-- parameter in the frame is written into the new frame at once (nothing
-- can see that frame yet); the writes to a parameter elsewhere are returned,
-- to be made once every argument is evaluated and the frame installed.
passArguments :: CallFrame s -> [(Var, Meaning s)] -> Env -> Machine s -> ST s [Run s ()]
passArguments fr = go
  where
    go [] _ _ = pure []
    go ((param, Meaning f r _ _) : rest) e m = do
      x <- r e m
      bad <- if f then hasFailed m else pure False
      if bad
        then pure []
        else case varHome param of
          Frame i -> writeFrame fr i x >> go rest e m
          _ -> (writeRun param 0 x :) <$> go rest e m
{-# INLINE passArguments #-}

compileStmt :: Ctx -> CStmt -> Run s Flow
compileStmt ctx
  | cxTrace ctx = tracedStmt ctx
  | otherwise = fastStmt ctx

fastStmt :: Ctx -> CStmt -> Run s Flow
fastStmt ctx = \case
  SAssign line target x ->
    -- MT-STMT-2: the right side is evaluated before the index of the target
    let xM = meaning ctx x
     in case target of
          LTVar v -> case varHome v of
            Data i -> toSlot (\m val -> writeSlot (mData m) i val)
            Frame i -> toSlot (\m val -> readSTRef (mFrame m) >>= \f -> writeFrame f i val)
            Mapped o
              | j <- heldSlot (cxCells ctx) o, j >= 0 ->
                  -- a held cell: the pattern of the number written straight
                  let !mask = cellMask (operandCell o)
                      store :: (Env -> Machine s -> ST s x) -> (x -> Word32) -> Run s Flow
                      store r pattern = \e m -> stepThen line m $ do
                        x <- r e m
                        bad <- if failsM xM then hasFailed m else pure False
                        if bad then pure Failing else Next <$ writeCellValue (mCells m) j (pattern x .&. mask)
                      {-# INLINE store #-}
                   in case cexprType x of
                        t
                          | intTyped t -> case intRunOf xM of !r -> store (runInt r) fromIntegral
                          | t == REAL -> case realRunOf xM of !r -> store (runReal r) realBits
                        _ -> generic
            _ -> generic
            where
              generic =
                let w = writeRunIn ctx v 0
                 in \e m -> stepThen line m $ withValue xM e m $ \val -> Next <$ w val e m
              -- a slot of the data area or of the frame; a typed
              -- expression's number is boxed as the slot's value here,
              -- without calling its 'Value' closure
              toSlot :: (forall s'. Machine s' -> Value -> ST s' ()) -> Run s Flow
              toSlot write = case xM of
                Meaning canFail _ Computed (IntTyped r) ->
                  let assign mk = \e m -> stepThen line m $ do
                        n <- runInt r e m
                        bad <- if canFail then hasFailed m else pure False
                        if bad then pure Failing else Next <$ write m (mk n)
                      {-# INLINE assign #-}
                   in eachIntBox (cexprType x) assign
                Meaning canFail _ Computed (RealTyped r) -> \e m -> stepThen line m $ do
                  val <- runReal r e m
                  bad <- if canFail then hasFailed m else pure False
                  if bad then pure Failing else Next <$ write m (VReal val)
                _ -> \e m -> stepThen line m $ withValue xM e m $ \val -> Next <$ write m val
              {-# INLINE toSlot #-}
          LTIndex iline v ix ->
            let ix' = indexExpr ix
                ixM = meaning ctx ix'
                index = elementIndex pol iline v
                writers = V.generate (varElements v) (writeRunIn ctx v)
             in case (varHome v, intBounds v) of
                  (Data base, Just (lo, hi))
                    | intTyped (cexprType ix') ->
                        -- an element of the data area: the index as a number,
                        -- the bounds checked inline
                        let store i val m
                              | i >= lo && i <= hi = Next <$ writeSlot (mData m) (base + i - lo) val
                              | otherwise = indexNumber pol iline v m (toInteger i) >>= \k -> if k < 0 then pure Failing else Next <$ writeSlot (mData m) (base + k) val
                            {-# INLINE store #-}
                         in case ixM of
                              -- an index that is a variable of the data area is read here
                              Meaning _ _ (DataSlot j d') _ -> \e m -> stepThen line m $ withValue xM e m $ \val ->
                                readSlot (mData m) d' j >>= \iv -> store (numberOf iv) val m
                              _ ->
                                let !ri = intRunOf ixM
                                 in \e m -> stepThen line m $ withValue xM e m $ \val -> do
                                      i <- runInt ri e m
                                      bad <- if failsM ixM then hasFailed m else pure False
                                      if bad then pure Failing else store i val m
                  _ -> \e m -> stepThen line m $ withValue xM e m $ \val ->
                    withValue ixM e m $ \iv -> do
                      k <- index m iv
                      if k < 0
                        then pure Failing
                        else case writers V.!? k of
                          Just w -> Next <$ w val e m
                          Nothing -> Failing <$ malformed iline m
  SCall line fid args ->
    -- MT-STMT-3: the result is discarded
    let callM = computed True (compileCall ctx line fid args)
     in \e m -> stepThen line m $ withValue callM e m $ \_ -> pure Next
  SIf arms elseB ->
    -- MT-STMT-6: the first true test selects its branch, else ELSE
    let armsR = [(l, meaning ctx c, compileBlock ctx b) | (l, c, b) <- arms]
        !elseR = compileBlock ctx elseB
        firstLine = case arms of
          (l, _, _) : _ -> l
          [] -> 0
        go [] = elseR
        go ((l, cM, bR) : rest) = test l cM bR (go rest)
        test l cM bR restR = \e m -> withValue cM e m $ \case
          VBool True -> bR e m
          VBool False -> restR e m
          _ -> Failing <$ malformed l m
        {-# INLINE test #-}
     in case (armsR, elseB) of
          -- the step and the first test in one closure; no call for an
          -- absent ELSE
          ([(l, cM, bR)], []) -> \e m -> stepThen firstLine m (test l cM bR (\_ _ -> pure Next) e m)
          ((l, cM, bR) : rest, _) -> let !restR = go rest in \e m -> stepThen firstLine m (test l cM bR restR e m)
          ([], _) -> \e m -> stepThen firstLine m (elseR e m)
  SCase line sel arms elseB ->
    -- MT-STMT-8: the first arm with a matching value or inclusive range
    let selM = meaning ctx sel
        armsR = [(ranges, compileBlock ctx b) | (ranges, b) <- arms]
        !elseR = compileBlock ctx elseB
     in \e m -> stepThen line m $ withValue selM e m $ \v -> case valueToInteger v of
          Just k -> selectArm k armsR elseR e m
          Nothing -> Failing <$ malformed line m
  SWhile line c body ->
    -- MT-STMT-13: the test before each iteration
    let cM = meaning ctx c
        !bodyR = compileBlock ctx body
        loop e m = stepThen line m $ withValue cM e m $ \case
          VBool False -> pure Next
          VBool True ->
            bodyR e m >>= \case
              Next -> loop e m
              Exiting -> pure Next
              other -> pure other
          _ -> Failing <$ malformed line m
     in \e m -> stepThen line m (loop e m)
  SRepeat body uline c ->
    -- MT-STMT-14: the body first, the loop ends when the test is TRUE
    let cM = meaning ctx c
        !bodyR = compileBlock ctx body
        loop e m =
          bodyR e m >>= \case
            Exiting -> pure Next
            Next -> stepThen uline m $ withValue cM e m $ \case
              VBool True -> pure Next
              VBool False -> loop e m
              _ -> Failing <$ malformed uline m
            other -> pure other
     in \e m -> stepThen uline m (loop e m)
  SFor line cv start end by body -> compileFor ctx line cv start end by body
  SExit line -> \_ m -> stepThen line m (pure Exiting) -- MT-STMT-12
  SReturn line -> \_ m -> stepThen line m (pure Returning) -- MT-STMT-4, MT-STMT-5
  where
    pol = cxPolicies ctx
    stepThen line m k = do
      ok <- tick (pStepBudget pol) line m
      if ok then k else pure Failing

-- | MT-STMT-8: what the first arm of a CASE whose values or inclusive
-- ranges hold the selector gives, else the ELSE's.
selectArm :: Integer -> [([CaseRange], a)] -> a -> a
selectArm k arms elseA = case arms of
  [] -> elseA
  (ranges, a) : rest
    | any (\(lo, hi) -> lo <= k && k <= hi) ranges -> a
    | otherwise -> selectArm k rest elseA
{-# INLINE selectArm #-}

-- | FOR (MT-STMT-15..21, decisions A13, A14). The control variable takes the
-- start value; end and step are evaluated once after it (@for-bounds =
-- once@) or before every test (@every-iteration@). A test lets the body run
-- while cv <= end for a step >= 0, while cv >= end for a negative step. After
-- the body the increment depends on @for-at-type-max@:
--
-- * @stop-at-end@: cv + step is computed exactly; if it leaves the type's
--   range the loop ends there (cv keeps its last value), otherwise cv takes
--   it and the test follows. So @FOR u := 250 TO 255@ on USINT runs 6 times,
--   and @FOR i := 1 TO 10@ leaves i = 11 as usual. INTERNAL_OVERFLOW is not
--   touched.
-- * @follow-overflow-policy@: cv := cv + step is an ordinary addition under
--   the overflow policy, including its effect on INTERNAL_OVERFLOW: saturation
--   keeps cv at the maximum, wrap-around restarts it, so a loop to the type's
--   maximum never ends and meets the step budget (2030).
--
-- A step of 0 never passes the end: the loop runs until the budget (2030)
-- unless start > end.
compileFor :: Ctx -> Line -> Var -> CExpr -> CExpr -> CExpr -> [CStmt] -> Run s Flow
compileFor ctx line cv start end by body = \e m ->
  step m $ withValue startM e m $ \s0 -> do
    writeCv s0 e m
    case pForBounds pol of
      ForOnce -> withValue endM e m $ \en -> withValue stepM e m $ \st ->
        case (pForAtTypeMax pol, intRangeInt, valueToInt en, valueToInt st) of
          (StopAtEnd, Just (lo, hi), Just enI, Just stI) -> case varHome cv of
            -- the control variable read and written in place
            Data i ->
              let rd = \_ m' -> readSlot (mData m') zero i
                  wr = \x _ m' -> writeSlot (mData m') i x
                  loopBoxing box = intLoop rd wr box lo hi enI stI e m
                  {-# INLINE loopBoxing #-}
               in -- the new value boxed by code chosen here, not on every step
                  eachIntBox t loopBoxing
            _ -> intLoop readCv writeCv (intToValue t) lo hi enI stI e m
          _ -> loop (\_ _ k -> k en st) e m
      ForEveryIteration -> loop (\e' m' k -> withValue endM e' m' $ \en -> withValue stepM e' m' $ \st -> k en st) e m
  where
    pol = cxPolicies ctx
    step m k = do
      ok <- tick (pStepBudget pol) line m
      if ok then k else pure Failing
    startM = meaning ctx start
    endM = meaning ctx end
    stepM = meaning ctx by
    !bodyR = compileBlock ctx body
    readCv = readRun cv 0
    writeCv = writeRun cv 0
    t = varBasicType cv
    zero = defaultValue t
    intRangeInt = (\(lo, hi) -> (fromInteger lo, fromInteger hi) :: (Int, Int)) <$> intRange t
    -- test, body, increment, again; @bounds@ gives the end and the step that
    -- each test uses (the values computed once, or computed anew)
    loop bounds e m = go
      where
        go = step m $ bounds e m $ \en st -> do
          c <- readCv e m
          if forContinues zero st c en
            then
              bodyR e m >>= \case
                Next -> increment st e m >>= \case
                  Next -> go
                  Exiting -> pure Next
                  other -> pure other
                Exiting -> pure Next
                other -> pure other
            else pure Next
    -- inlined at both uses, each with its own bounds (left to GHC, it was
    -- no longer inlined once the FOR test and forNext were shared, and
    -- bounds was an unknown call with a new continuation every iteration)
    {-# INLINE loop #-}
    -- the same loop for the common case, an integer control variable with
    -- bounds evaluated once and @stop-at-end@, on machine integers
    intLoop rd wr box lo hi enI stI e m =
      rd e m >>= \c -> case valueToInt c of
        Just ci -> go ci
        Nothing -> Failing <$ malformed line m
      where
        -- @ci@ is the control variable's value, known without reading it
        -- again: the start value, or the value just written
        go !ci = do
          ok <- tick (pStepBudget pol) line m
          if not ok
            then pure Failing
            else
              if if stI < 0 then ci >= enI else ci <= enI
                then
                  bodyR e m >>= \case
                    Next ->
                      -- the body may have assigned the control variable
                      rd e m >>= \c' -> case valueToInt c' of
                        Just ci'
                          | ci' + stI < lo || ci' + stI > hi -> pure Next
                          | otherwise -> let n = ci' + stI in (wr $! box n) e m >> go n
                        Nothing -> Failing <$ malformed line m
                    Exiting -> pure Next
                    other -> pure other
                else pure Next
    {-# INLINE intLoop #-}
    -- Next: go on testing; Exiting: the loop ends; Failing: an error
    increment s e m = do
      c <- readCv e m
      case forNext pol t intRangeInt c s of
        LeavesRange -> pure Exiting
        NotANumber -> Failing <$ malformed line m
        NextValue n -> Next <$ writeCv n e m
        NextSum o -> do
          n <- outcome line m o
          bad <- hasFailed m
          if bad then pure Failing else Next <$ writeCv n e m

-- | The test before each iteration of a FOR (MT-STMT-18): with a step of at
-- least @zero@ (the step type's 0) the body runs while cv <= end, with a
-- negative step while cv >= end (MT-STMT-21 a).
forContinues :: Value -> Value -> Value -> Value -> Bool
forContinues zero s c en
  | numCompare s zero == LT = numCompare c en /= LT
  | otherwise = numCompare c en /= GT
{-# INLINE forContinues #-}

-- | What follows the body of a FOR, under @for-at-type-max@ (decision A14,
-- MT-STMT-21 b): the control variable's next value, the addition under the
-- overflow policy with its effect on INTERNAL_OVERFLOW (@follow-overflow-policy@),
-- or the end of the loop because cv + step leaves the type's range (given
-- as machine integers, for an integer control variable). A plain value is
-- not made an operator's outcome: the fast loop would build and take
-- apart one on every iteration.
data ForNext = NextValue Value | NextSum O.Outcome | LeavesRange | NotANumber

forNext :: Policies -> BasicType -> Maybe (Int, Int) -> Value -> Value -> ForNext
forNext pol t range c s = case pForAtTypeMax pol of
  StopAtEnd -> case (valueToInt c, valueToInt s, range) of
    (Just ci, Just si, Just (lo, hi))
      | ci + si < lo || ci + si > hi -> LeavesRange
      | otherwise -> NextValue (intToValue t (ci + si))
    _ -> case (c, s) of
      (VReal x, VReal y) -> NextValue (VReal (x + y))
      _ -> NotANumber
  FollowOverflowPolicy -> NextSum (O.arith pol OpAdd c s)
{-# INLINE forNext #-}

-- | Numeric order of two values of one type (integers and bit strings by
-- their number, REAL by IEEE order with NaN treated as equal).
numCompare :: Value -> Value -> Ordering
numCompare a b = case (valueToInt a, valueToInt b, a, b) of
  (Just x, Just y, _, _) -> compare x y
  (_, _, VReal x, VReal y)
    | x < y -> LT
    | x > y -> GT
    | otherwise -> EQ
  _ -> EQ

--------------------------------------------------------------------------------
-- Tracing (#24)
--
-- The closures of a traced translation. They share with the fast ones
-- every piece that gives a meaning (the reads and writes of variables,
-- 'elementIndex', 'selectArm', 'forContinues', 'forNext', 'outcome',
-- 'tick', 'passArguments'), use the reference operators of
-- "Stref.Operators" where the fast closures have their fast paths (FastSpec
-- checks that the two agree), and tell the machine's tracer what they read,
-- wrote and chose, the decisions taken from the values those functions
-- returned. Every traced expression is a plain closure that may fail: no
-- leaves, no typed closures, speed does not matter here.

-- | Tell the machine's tracer.
traceEvent :: Machine s -> Event -> ST s ()
traceEvent m ev = mapM_ (\r -> modifySTRef' r (emit ev)) (mTrace m)

traced :: Run s Value -> Meaning s
traced = computed True

-- | Run an expression, then the continuation with its value, unless the
-- expression failed (then its value, never used, is the result).
thenValue :: Meaning s -> Env -> Machine s -> (Value -> ST s Value) -> ST s Value
thenValue (Meaning _ r _ _) e m k = do
  x <- r e m
  bad <- hasFailed m
  if bad then pure x else k x

-- | The traced meaning of an expression; its reads and decisions are told
-- at the line of the statement it belongs to ('cxLine'), its runtime errors
-- raised at its own line as in 'fastMeaning'.
tracedMeaning :: Ctx -> CExpr -> Meaning s
tracedMeaning ctx = \case
  CLit v -> traced (\_ _ -> pure v)
  CRead v ->
    let r = readRunIn ctx v 0
     in traced $ \e m -> r e m >>= \x -> x <$ traceEvent m (Read line (varName v) (showValue x))
  CReadIndex iline v ix ->
    let ixM = meaning ctx (indexExpr ix)
        elements = V.generate (varElements v) (readRunIn ctx v)
     in traced $ \e m -> thenValue ixM e m $ \iv -> do
          k <- tracedIndex pol line iline v m iv
          if k < 0
            then pure iv
            else case elements V.!? k of
              Just r -> r e m >>= \x -> x <$ traceEvent m (Read line (elementName v k) (showValue x))
              Nothing -> malformed iline m
  CConv from to x -> unaryOp x $ \m v -> do
    let w = convert pol from to v -- MT-CONV-5
    mapM_ (traceEvent m . Rule line) (conversionDecisions from to v w)
    pure w
  CNeg l t x -> unaryOp x $ \m v -> tracedOutcome pol line l m t ("-(" <> showValue v <> ")") Nothing (O.negateValue pol v) -- MT-OP-4, MT-OP-6
  CNot _ x -> unaryOp x $ \_ v -> pure (O.notValue v) -- MT-OP-14
  CArith l op t a b -> binaryOp a b $ \m x y ->
    let byZero = if op `elem` [OpDiv, OpMod] && isZero y then Just op else Nothing
     in tracedOutcome pol line l m t (showValue x <> " " <> arithSymbol op <> " " <> showValue y) byZero (O.arith pol op x y) -- MT-OP-4..10
  CCompare op _ a b -> binaryOp a b $ \_ x y -> pure (boolValue (O.compareValues op x y)) -- MT-OP-11
  CLogic op t a b -> case (pShortCircuit pol, t, op) of
    -- decision A17, as in 'fastMeaning'
    (ShortCircuit, BOOL, OpAnd) -> shortCircuit op a b (VBool False)
    (ShortCircuit, BOOL, OpOr) -> shortCircuit op a b (VBool True)
    _ -> binaryOp a b $ \_ x y -> pure (O.logic op x y) -- MT-OP-12..14
  CCall l fid _ args -> traced (tracedCall ctx l fid args)
  CExpt l t a b -> binaryOp a b $ \m x y ->
    tracedOutcome pol line l m t ("EXPT(" <> showValue x <> ", " <> showValue y <> ")") Nothing (O.expt pol x y) -- MT-OP-20
  where
    pol = cxPolicies ctx
    line = cxLine ctx
    unaryOp x f = let xM = meaning ctx x in traced $ \e m -> thenValue xM e m (f m)
    -- left to right (decision A18)
    binaryOp a b f =
      let aM = meaning ctx a
          bM = meaning ctx b
       in traced $ \e m -> thenValue aM e m $ \x -> thenValue bM e m $ \y -> f m x y
    shortCircuit op a b decisive =
      let aM = meaning ctx a
          bM = meaning ctx b
       in traced $ \e m -> thenValue aM e m $ \x ->
            if x == decisive
              then x <$ traceEvent m (Rule line (ruled ["A17"] "short-circuit" (showValue x <> " " <> logicWord op <> " ...: the right operand is not evaluated")))
              else thenValue bM e m $ \y -> pure (O.logic op x y)
    isZero = \case
      VReal r -> r == 0
      y -> valueToInteger y == Just 0

-- | Apply an operator's outcome as the fast closures do ('outcome'), after
-- telling the decisions it shows.
tracedOutcome :: Policies -> Line -> Line -> Machine s -> BasicType -> Text -> Maybe ArithOp -> O.Outcome -> ST s Value
tracedOutcome pol eventLine line m t expr byZero o = do
  flagBefore <- (/= 0) <$> MU.unsafeRead (mCounters m) ixOverflow
  mapM_ (traceEvent m . Rule eventLine) (outcomeDecisions pol t expr flagBefore byZero o)
  outcome line m o

-- | What an operator's outcome shows: an overflow (MT-OP-6) and its effect
-- on INTERNAL_OVERFLOW (MT-OP-7; a FALSE is told when it clears a TRUE), a
-- division or MOD by zero (MT-OP-8, MT-OP-9), a trap. @byZero@ is the
-- operator when its right operand is zero.
outcomeDecisions :: Policies -> BasicType -> Text -> Bool -> Maybe ArithOp -> O.Outcome -> [Decision]
outcomeDecisions pol t expr flagBefore byZero = \case
  Right (v, flag) ->
    let shown = expr <> " = " <> showValue v
        zero = case byZero of
          Just OpMod -> [ruled ["MT-OP-8"] "mod-zero" (shown <> ": MOD by 0 gives 0")]
          Just OpDiv -> [ruled ["MT-OP-9"] divZeroPolicy (shown <> ": division by 0")]
          _ -> []
        overflow = case flag of
          Just True -> [ruled ["MT-OP-6"] overflowPolicy (shown <> ": " <> overflowWords), decision ["MT-OP-7"] "INTERNAL_OVERFLOW := TRUE"]
          Just False | flagBefore -> [decision ["MT-OP-7"] "INTERNAL_OVERFLOW := FALSE (this operation did not overflow)"]
          _ -> []
     in zero ++ overflow
  Left code
    | code == errDivisionByZero -> [ruled ["MT-OP-9"] divZeroPolicy (expr <> ": division by 0 is runtime error 2020")]
    | code == trapOverflow -> [ruled ["MT-OP-6"] overflowPolicy (expr <> " overflows " <> typeName t <> ": trap")]
    | code == trapDivisionByZero -> [ruled ["MT-OP-9"] "div-zero" (expr <> ": division by 0 traps")]
    | code == errModZero -> [ruled ["MT-OP-8"] "mod-zero" (expr <> ": MOD by 0 is an error")]
    | otherwise -> []
  where
    isReal = t == REAL
    divZeroPolicy = if isReal then "real-div-zero" else "div-zero"
    overflowPolicy = if isReal then "real-overflow" else "overflow"
    overflowWords
      | isReal = case pRealOverflow pol of
          RealOverflowSaturate -> "REAL saturates to the largest finite value"
          RealOverflowIeee -> "REAL overflows to infinity"
      | otherwise =
          let width = case pArithWidth pol of
                OperandType -> typeName t
                Promote32 -> "the 32-bit result"
           in width <> case pOverflow pol of
                Saturate -> " saturates"
                Wrap -> " wraps around"
                Trap -> " traps"

-- | What a conversion decided (Table 4-6), told when it changed the number:
-- a REAL made an integer by @real-to-int@ (MT-CONV-9), a narrowing that
-- kept the low bits or saturated (@narrow-int@, MT-CONV-13), a bit pattern
-- read with another sign (MT-CONV-5).
conversionDecisions :: BasicType -> BasicType -> Value -> Value -> [Decision]
conversionDecisions from to v w
  | from == to || BOOL `elem` [from, to] = []
  | otherwise = case (v, valueToInteger v, valueToInteger w) of
      (VReal r, _, Just n)
        | realToRational r /= Just (fromInteger n) -> [ruled ["MT-CONV-9"] "real-to-int" shown]
      (_, Just k, Just n)
        | k /= n && typeBits to < typeBits from -> [ruled ["MT-CONV-13"] "narrow-int" shown]
        | k /= n -> [decision ["MT-CONV-5"] (shown <> ": the same bits")]
      _ -> []
  where
    shown = conversionName from to <> "(" <> showValue v <> ") = " <> showValue w

-- | 'elementIndex', telling what the @index-out-of-range@ policy made of an
-- index outside the array's bounds (MT-ARR-8).
tracedIndex :: Policies -> Line -> Line -> Var -> Machine s -> Value -> ST s Int
tracedIndex pol eventLine line v m iv = do
  k <- elementIndex pol line v m iv
  case (varType v, valueToInteger iv) of
    (Array lo hi _, Just n)
      | n < lo || n > hi -> do
          outcomeText <-
            if k >= 0
              then pure ("element " <> elementName v k <> " is used")
              else (\err -> "runtime error " <> tshow (reCode err)) <$> readSTRef (mError m)
          traceEvent m . Rule eventLine . ruled ["MT-ARR-8"] "index-out-of-range" $
            varName v <> "[" <> tshow n <> "] is outside " <> tshow lo <> ".." <> tshow hi <> ": " <> outcomeText
    _ -> pure ()
  pure k

-- | The name of element @k@ (0-based) of an array, with its index: @V[3]@.
elementName :: Var -> Int -> Text
elementName v k = case varType v of
  Array lo _ _ -> varName v <> "[" <> tshow (lo + toInteger k) <> "]"
  Basic _ -> varName v

-- | A call as 'compileCall' makes it, telling the arguments once all are
-- evaluated (decision A18) and the result.
tracedCall :: Ctx -> Line -> FunId -> [CExpr] -> Run s Value
tracedCall ctx line fid args = case IM.lookup fid (cxFunctions ctx) of
  Nothing -> \_ m -> malformed line m
  Just fn ->
    let argsM = map (meaning ctx) args
        params = fnParams fn
     in \e m -> do
          values <- argumentValues argsM e m
          case values of
            Nothing -> pure (VBool False)
            Just xs -> do
              traceEvent m (Call at (fnName fn) [(varName p, showValue x) | (p, x) <- zip params xs])
              fr <- startFrame (fnFrame fn)
              later <- passArguments fr [(p, Meaning False (\_ _ -> pure x) (Constant x) Untyped) | (p, x) <- zip params xs] e m
              -- runtime error 2050 is told by the runner, with MT-POU-9
              r <- inFrame line fn fr later e m
              bad <- hasFailed m
              if bad then pure r else r <$ traceEvent m (Return at (fnName fn) [(fnName fn, showValue r)])
  where
    at = cxLine ctx
    argumentValues [] _ _ = pure (Just [])
    argumentValues (Meaning _ r _ _ : rest) e m = do
      x <- r e m
      bad <- hasFailed m
      if bad then pure Nothing else fmap (x :) <$> argumentValues rest e m

-- | 'tick' (the runtime error 2030 it may raise is told with the rule
-- MT-EXEC-7 by the runner, after the error: "Stref.Execution").
tracedStep :: Policies -> Line -> Machine s -> ST s Flow -> ST s Flow
tracedStep pol line m k = do
  ok <- tick (pStepBudget pol) line m
  if ok then k else pure Failing

-- | A loop ended after @n@ iterations, unless by a runtime error.
loopEnds :: Machine s -> Line -> Int -> Flow -> ST s Flow
loopEnds m line n flow
  | flow == Failing = pure flow
  | otherwise = flow <$ traceEvent m (LoopExit line n)

-- | The traced closure of a statement: its steps as 'fastStmt' counts them,
-- its expressions translated at its line.
tracedStmt :: Ctx -> CStmt -> Run s Flow
tracedStmt ctx = \case
  SAssign line target x ->
    -- MT-STMT-2: the right side is evaluated before the index of the target
    let xM = meaning (at line) x
     in case target of
          LTVar v ->
            let w = writeRunIn ctx v 0
             in \e m -> step line m $ withValue xM e m $ \val -> w val e m >> wrote m line (varName v) val
          LTIndex iline v ix ->
            let ixM = meaning (at line) (indexExpr ix)
                writers = V.generate (varElements v) (writeRunIn ctx v)
             in \e m -> step line m $ withValue xM e m $ \val -> withValue ixM e m $ \iv -> do
                  k <- tracedIndex pol line iline v m iv
                  if k < 0
                    then pure Failing
                    else case writers V.!? k of
                      Just w -> w val e m >> wrote m line (elementName v k) val
                      Nothing -> Failing <$ malformed iline m
  SCall line fid args ->
    -- MT-STMT-3: the result is discarded
    let callM = traced (tracedCall (at line) line fid args)
     in \e m -> step line m $ withValue callM e m $ \_ -> completed m line
  SIf arms elseB ->
    -- MT-STMT-6: the first true test selects its branch, else ELSE
    let elseR = compileBlock ctx elseB
        firstLine = case arms of
          (l, _, _) : _ -> l
          [] -> 0
        chain _ [] = elseR
        chain first ((l, c, b) : rest) =
          let cM = meaning (at l) c
              bR = compileBlock ctx b
              restR = chain False rest
              onTrue = "condition TRUE: " <> if first then "THEN" else "this ELSIF"
              onFalse = case (rest, elseB) of
                ([], []) -> "condition FALSE: nothing runs"
                ([], _) -> "condition FALSE: ELSE"
                _ -> "condition FALSE"
           in \e m -> withValue cM e m $ \case
                VBool True -> traceEvent m (Branch l onTrue) >> bR e m
                VBool False -> traceEvent m (Branch l onFalse) >> restR e m
                _ -> Failing <$ malformed l m
        !ifR = chain True arms
     in \e m -> step firstLine m (ifR e m)
  SCase line sel arms elseB ->
    -- MT-STMT-8: the first arm with a matching value or inclusive range
    let selM = meaning (at line) sel
        armsR = [(ranges, Just (ranges, compileBlock ctx b)) | (ranges, b) <- arms]
        elseR = compileBlock ctx elseB
        labels ranges = T.intercalate ", " [if lo == hi then tshow lo else tshow lo <> ".." <> tshow hi | (lo, hi) <- ranges]
     in \e m -> step line m $ withValue selM e m $ \v -> case valueToInteger v of
          Just k -> case selectArm k armsR Nothing of
            Just (ranges, bR) -> traceEvent m (Branch line ("selector " <> tshow k <> " matches the labels " <> labels ranges)) >> bR e m
            Nothing -> traceEvent m (Branch line ("selector " <> tshow k <> " matches no label: " <> if null elseB then "nothing runs" else "ELSE")) >> elseR e m
          Nothing -> Failing <$ malformed line m
  SWhile line c body ->
    -- MT-STMT-13: the test before each iteration
    let cM = meaning (at line) c
        bodyR = compileBlock ctx body
        loop n e m = step line m $ withValue cM e m $ \case
          VBool False -> traceEvent m (Branch line "condition FALSE: the loop ends") >> loopEnds m line n Next
          VBool True -> do
            traceEvent m (Branch line "condition TRUE: the body runs")
            traceEvent m (Iteration line (n + 1))
            bodyR e m >>= \case
              Next -> loop (n + 1) e m
              Exiting -> loopEnds m line (n + 1) Next
              other -> loopEnds m line (n + 1) other
          _ -> Failing <$ malformed line m
     in \e m -> step line m $ do
          traceEvent m (Rule line (decision ["MT-STMT-13"] "the condition is tested before each iteration"))
          traceEvent m (LoopEnter line "WHILE loop")
          loop 0 e m
  SRepeat body uline c ->
    -- MT-STMT-14: the body first, the loop ends when the test is TRUE
    let cM = meaning (at uline) c
        bodyR = compileBlock ctx body
        loop n e m = do
          traceEvent m (Iteration uline (n + 1))
          bodyR e m >>= \case
            Exiting -> loopEnds m uline (n + 1) Next
            Next -> step uline m $ withValue cM e m $ \case
              VBool True -> traceEvent m (Branch uline "condition TRUE: the loop ends") >> loopEnds m uline (n + 1) Next
              VBool False -> traceEvent m (Branch uline "condition FALSE: again") >> loop (n + 1) e m
              _ -> Failing <$ malformed uline m
            other -> loopEnds m uline (n + 1) other
     in \e m -> step uline m $ do
          traceEvent m (Rule uline (decision ["MT-STMT-14"] "the body runs first; the condition is tested after each iteration"))
          traceEvent m (LoopEnter uline "REPEAT loop")
          loop 0 e m
  SFor line cv start end by body -> tracedFor (at line) line cv start end by body
  SExit line -> \_ m -> step line m (Exiting <$ traceEvent m (Statement line)) -- MT-STMT-12
  SReturn line -> \_ m -> step line m (Returning <$ traceEvent m (Statement line)) -- MT-STMT-4, MT-STMT-5
  where
    pol = cxPolicies ctx
    at l = ctx {cxLine = l}
    step = tracedStep pol
    wrote m line name val = traceEvent m (Wrote line name (showValue val)) >> completed m line
    completed m line = Next <$ traceEvent m (Statement line)

-- | The traced FOR: the loop of 'compileFor' that works on values (the
-- bounds once or before every test, @for-bounds@, MT-STMT-19; the
-- increment by 'forNext'), telling the bounds, each iteration and the
-- control variable's values.
tracedFor :: Ctx -> Line -> Var -> CExpr -> CExpr -> CExpr -> [CStmt] -> Run s Flow
tracedFor ctx line cv start end by body = \e m ->
  step m $ withValue startM e m $ \s0 -> do
    writeCv s0 e m
    traceEvent m (Wrote line name (showValue s0))
    case pForBounds pol of
      ForOnce -> withValue endM e m $ \en -> withValue stepM e m $ \st -> do
        traceEvent m (Rule line (ruled ["MT-STMT-19"] "for-bounds" "end and step are evaluated once, before the first test"))
        traceEvent m (LoopEnter line (name <> " from " <> showValue s0 <> " to " <> showValue en <> " by " <> showValue st))
        loop (\_ _ k -> k en st) e m
      ForEveryIteration -> do
        traceEvent m (Rule line (ruled ["MT-STMT-19"] "for-bounds" "end and step are evaluated again before every test"))
        traceEvent m (LoopEnter line (name <> " from " <> showValue s0 <> ", end and step evaluated before each test"))
        loop (\e' m' k -> withValue endM e' m' $ \en -> withValue stepM e' m' $ \st -> k en st) e m
  where
    pol = cxPolicies ctx
    step = tracedStep pol line
    name = varName cv
    startM = meaning ctx start
    endM = meaning ctx end
    stepM = meaning ctx by
    bodyR = compileBlock ctx body
    readCv = readRun cv 0
    writeCv = writeRun cv 0
    t = varBasicType cv
    zero = defaultValue t
    range = (\(lo, hi) -> (fromInteger lo, fromInteger hi)) <$> intRange t
    loop bounds e m = go 0
      where
        go n = step m $ bounds e m $ \en st -> do
          c <- readCv e m
          if forContinues zero st c en
            then do
              traceEvent m (Iteration line (n + 1))
              bodyR e m >>= \case
                Next ->
                  increment st e m >>= \case
                    Next -> go (n + 1)
                    Exiting -> loopEnds m line (n + 1) Next
                    other -> loopEnds m line (n + 1) other
                Exiting -> loopEnds m line (n + 1) Next
                other -> loopEnds m line (n + 1) other
            else loopEnds m line n Next
    increment s e m = do
      c <- readCv e m
      case forNext pol t range c s of
        LeavesRange -> do
          traceEvent m . Rule line . ruled ["MT-STMT-21"] "for-at-type-max" $
            showValue c <> " + " <> showValue s <> " leaves " <> typeName t <> ": the loop ends, " <> name <> " keeps " <> showValue c
          pure Exiting
        NotANumber -> Failing <$ malformed line m
        NextValue n -> wroteCv n
        NextSum o -> do
          n <- tracedOutcome pol line line m t (showValue c <> " + " <> showValue s) Nothing o
          bad <- hasFailed m
          if bad then pure Failing else wroteCv n
      where
        wroteCv n = Next <$ (writeCv n e m >> traceEvent m (Wrote line name (showValue n)))

arithSymbol :: ArithOp -> Text
arithSymbol = \case
  OpAdd -> "+"
  OpSub -> "-"
  OpMul -> "*"
  OpDiv -> "/"
  OpMod -> "MOD"

logicWord :: LogicOp -> Text
logicWord = \case
  OpAnd -> "AND"
  OpOr -> "OR"
  OpXor -> "XOR"

tshow :: Show a => a -> Text
tshow = T.pack . show
