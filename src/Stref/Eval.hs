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
{-# LANGUAGE RankNTypes #-}
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
  , compileExpr
  , compileBlock
  ) where

import Control.Monad.ST (ST)
import qualified Data.IntMap.Strict as IM
import Data.Int (Int32)
import Data.IntMap.Strict (IntMap)
import Data.STRef
import qualified Data.Vector as V
import qualified Data.Vector.Mutable as MV
import qualified Data.Vector.Unboxed.Mutable as MU
import Stref.Checked
import Stref.Diagnostics
import Stref.Eval.Fast
import Stref.Operands
import qualified Stref.Operators as O
import Stref.Policy
import Stref.Types
import Stref.Values

-- | The state one module call works on: mutable slots, valid inside one
-- 'runST'.
data Machine s = Machine
  { mData :: !(MV.MVector s Value) -- ^ the module data area (MT-MAP-1)
  , mFrame :: !(STRef s (MV.MVector s Value)) -- ^ the active function call's frame (MT-SCOPE-7)
  , mMemory :: !(STRef s Memory) -- ^ the PLC operands
  , mCounters :: !(MU.MVector s Int)
  -- ^ steps used of the budget (MT-EXEC-7), INTERNAL_OVERFLOW (MT-OP-7),
  -- OUTPUT1..3 (MT-SIG-4), at the indices below
  }

ixSteps, ixOverflow :: Int
ixSteps = 0
ixOverflow = 1

-- | OUTPUTn is counter 1 + n.
ixOutput :: Int -> Int
ixOutput n = 1 + n

-- | A machine with the data area taken from the retained slots, or else
-- every slot at its type default (so reading a slot before any write gives
-- the default, as MT-VAR-3 asks); OUTPUT1 TRUE, the others and the flag
-- FALSE, no steps used.
newMachine :: CompiledModule -> IntMap Value -> Memory -> (Bool, Bool, Bool) -> ST s (Machine s)
newMachine cm retained mem (o1, o2, o3) = do
  d <- V.thaw (V.imap (\k def -> IM.findWithDefault def k retained) (cmDataDefaults cm))
  f <- MV.replicate 0 (VBool False)
  fr <- newSTRef f
  mr <- newSTRef mem
  cs <- MU.replicate 5 0
  MU.write cs (ixOutput 1) (fromEnum o1)
  MU.write cs (ixOutput 2) (fromEnum o2)
  MU.write cs (ixOutput 3) (fromEnum o3)
  pure (Machine d fr mr cs)

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
  mem <- readSTRef (mMemory m)
  cs <- mapM (MU.read (mCounters m)) [0 .. 4]
  case cs of
    [steps, o, a, b, c] -> pure (Snapshot d mem (a /= 0, b /= 0, c /= 0) (o /= 0) steps)
    _ -> pure (Snapshot d mem (False, False, False) False 0)

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
getMemory = Exec $ \_ m -> Done <$> readSTRef (mMemory m)

setOverflow :: Bool -> Exec s ()
setOverflow b = Exec $ \_ m -> Done <$> MU.unsafeWrite (mCounters m) ixOverflow (fromEnum b)

-- | MT-POU-9, MT-LIM-1: at most 16 nested function calls.
maxCallDepth :: Int
maxCallDepth = 16

-- | Reported when the checked program is inconsistent (a value of the wrong
-- type, a missing function): a bug of the checker, never of the ST program.
errMalformed :: ErrorCode
errMalformed = 9999

-- | One step of the budget; exceeding it is runtime error 2030 at the line
-- being executed (MT-EXEC-7).
tick :: Int -> Line -> Exec s ()
tick budget line = Exec $ \_ m -> do
  s <- MU.unsafeRead (mCounters m) ixSteps
  if s >= budget
    then pure (Failed (runtimeError errExecutionTime line))
    else Done <$> MU.unsafeWrite (mCounters m) ixSteps (s + 1)
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

writeSlot :: MV.MVector s Value -> Int -> Value -> ST s ()
writeSlot vec k x
  | k >= 0 && k < MV.length vec = MV.unsafeWrite vec k x
  | otherwise = pure ()
{-# INLINE writeSlot #-}

-- | Read element @off@ (0-based) of a variable; 0 for a scalar. The home
-- is inspected when the closure is built, not when it runs.
readElement :: Var -> Int -> Exec s Value
readElement v off = case varHome v of
  Data i -> let k = i + off in Exec $ \_ m -> Done <$> readSlot (mData m) def k
  Frame i -> let k = i + off in Exec $ \_ m -> readSTRef (mFrame m) >>= \f -> Done <$> readSlot f def k
  Mapped o -> let o' = elementOperand o off in Exec $ \_ m -> (\mem -> Done (readOperand mem o' t)) <$> readSTRef (mMemory m)
  SignalInput n -> Exec $ \e _ -> pure (Done (VBool (signal n (envInputs e))))
  SignalOutput n -> Exec $ \_ m -> Done . VBool . (/= 0) <$> MU.unsafeRead (mCounters m) (ixOutput (clampSignal n))
  OverflowFlag -> Exec $ \_ m -> Done . VBool . (/= 0) <$> MU.unsafeRead (mCounters m) ixOverflow
  where
    t = varBasicType v
    def = defaultValue t

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
writeElement v off = case varHome v of
  Data i -> let k = i + off in \x -> Exec $ \_ m -> Done <$> writeSlot (mData m) k x
  Frame i -> let k = i + off in \x -> Exec $ \_ m -> readSTRef (mFrame m) >>= \f -> Done <$> writeSlot f k x
  Mapped o -> let o' = elementOperand o off in \x -> Exec $ \_ m -> Done <$> modifySTRef' (mMemory m) (writeOperand o' x)
  SignalInput _ -> \_ -> pure ()
  SignalOutput n
    | n >= 1 && n <= 3 -> \x -> Exec $ \_ m -> Done <$> MU.unsafeWrite (mCounters m) (ixOutput n) (fromEnum (boolOf x))
    | otherwise -> \_ -> pure ()
  OverflowFlag -> \x -> setOverflow (boolOf x)
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
-- (EXIT, MT-STMT-12) or leaving the function or program (RETURN, MT-STMT-4,
-- MT-STMT-5).
data Flow = Next | Exiting | Returning
  deriving (Eq, Show)

-- | A translated module: the program body and the functions, each a
-- closure.
data CompiledModule = CompiledModule
  { cmBody :: forall s. Exec s Flow
  , cmFunctionMeanings :: IntMap Function
  , cmDataDefaults :: V.Vector Value -- ^ the initial data area: every slot at its type default
  }

-- | The meaning of a function: arguments to result.
newtype Function = Function (forall s. [Value] -> Exec s Value)

data Ctx = Ctx
  { cxPolicies :: Policies
  , cxFunctions :: IntMap Function
  }

-- | Translate the whole module once. Functions refer to each other through
-- the lazily built table of meanings (a knot: each function is translated
-- once, however often it is called).
compileModule :: Policies -> CModule -> CompiledModule
compileModule pol cm = CompiledModule (compileBlock ctx (cpBody prog)) funs defaults
  where
    ctx = Ctx pol funs
    funs = IM.map (\f -> Function (compileFunction ctx f)) (cmFunctions cm)
    prog = cmProgram cm
    defaults =
      slotDefaults dataSlot (cmDataSize cm) $
        map viVar (cmInits cm) ++ cpInputs prog ++ cpInOuts prog ++ cpOutputs prog ++ map snd (cmNamed cm)
    dataSlot = \case
      Data i -> Just i
      _ -> Nothing

-- | A function call in a fresh frame (MT-SCOPE-7): the result slot starts
-- at its type default, the parameters take the arguments in declaration
-- order (MT-POU-5), the locals their initial values; the result is the
-- result slot when the body ends or returns (MT-POU-4, MT-STMT-4).
compileFunction :: Ctx -> CFunction -> [Value] -> Exec s Value
compileFunction ctx f = \args -> do
  Exec $ \_ m -> V.thaw template >>= \fr -> Done <$> writeSTRef (mFrame m) fr
  mapM_ (uncurry writeScalar) (zip (cfParams f) args)
  mapM_ initVar (cfLocals f)
  _ <- body
  Exec $ \_ m -> readSTRef (mFrame m) >>= \fr -> Done <$> readSlot fr result 0
  where
    body = compileBlock ctx (cfBody f)
    result = defaultValue (cfResult f)
    frameSlot = \case
      Frame i -> Just i
      _ -> Nothing
    -- slot 0 is the result, at its default; the others at their types'
    -- defaults until written
    template =
      slotDefaults frameSlot (cfFrameSize f) (cfParams f ++ map viVar (cfLocals f))
        V.// [(0, result)]

-- | A statement list: stops at the first EXIT or RETURN.
compileBlock :: Ctx -> [CStmt] -> Exec s Flow
compileBlock ctx = go . map (compileStmt ctx)
  where
    go [] = pure Next
    go (s : ss) =
      let rest = go ss
       in s >>= \case
            Next -> rest
            other -> pure other

-- | Apply an operator outcome: a runtime error at the node's line, or the
-- value with its effect on INTERNAL_OVERFLOW (MT-OP-7).
outcome :: Line -> O.Outcome -> Exec s Value
outcome line = \case
  Left code -> failWith code line
  Right (v, flag) -> case flag of
    Just b -> Exec $ \_ m -> Done v <$ MU.unsafeWrite (mCounters m) ixOverflow (fromEnum b)
    Nothing -> pure v
{-# INLINE outcome #-}

asBool :: Line -> Value -> Exec s Bool
asBool line = \case
  VBool b -> pure b
  _ -> failWith errMalformed line

asInteger :: Line -> Value -> Exec s Integer
asInteger line v = maybe (failWith errMalformed line) pure (valueToInteger v)

-- | The 0-based element of an array for an index value, under the
-- @index-out-of-range@ policy (MT-ARR-2, MT-ARR-8, decision A23).
elementIndex :: Policies -> Line -> Var -> Value -> Exec s Int
elementIndex pol line v = case varType v of
  Array lo hi _
    | lo >= toInteger dintMin && hi <= toInteger dintMax ->
        -- the common case without Integer: a DINT index within DINT bounds
        let loI = fromInteger lo :: Int
            hiI = fromInteger hi :: Int
         in \case
              VDInt k32
                | k >= loI && k <= hiI -> pure (k - loI)
                where
                  k = fromIntegral k32
              iv -> elementIndexRef pol line v iv
  _ -> elementIndexRef pol line v
  where
    dintMin = minBound :: Int32
    dintMax = maxBound :: Int32

elementIndexRef :: Policies -> Line -> Var -> Value -> Exec s Int
elementIndexRef pol line v iv = do
  k <- asInteger line iv
  case varType v of
    Basic _ -> failWith errMalformed line
    Array lo hi _
      | k >= lo && k <= hi -> pure (fromInteger (k - lo))
      | otherwise -> case pIndexOutOfRange pol of
          IndexError -> failWith errIndex line -- MT-ERR-2015
          IndexTrap -> failWith trapIndex line
          IndexClamp -> pure (fromInteger (max lo (min hi k) - lo))

compileExpr :: Ctx -> CExpr -> Exec s Value
compileExpr ctx = \case
  CLit v -> pure v
  CRead v -> readScalar v
  CReadIndex line v ix ->
    let ixE = compileExpr ctx ix
     in ixE >>= elementIndex pol line v >>= readElement v
  CConv from to e ->
    let eE = compileExpr ctx e
        conv = convertFast pol from to
     in conv <$> eE -- MT-CONV-5
  CNeg line _ e ->
    let eE = compileExpr ctx e
     in eE >>= outcome line . O.negateValue pol -- MT-OP-4, MT-OP-6
  CNot _ e -> O.notValue <$> compileExpr ctx e -- MT-OP-14
  CArith line op _ a b ->
    let aE = compileExpr ctx a
        bE = compileExpr ctx b
        f = arithFast pol op
     in do
          x <- aE
          y <- bE
          outcome line (f x y)
  CCompare op _ a b ->
    let aE = compileExpr ctx a
        bE = compileExpr ctx b
        f = compareFast op
     in do
          x <- aE
          y <- bE
          pure (VBool (f x y))
  CLogic op t a b ->
    let aE = compileExpr ctx a
        bE = compileExpr ctx b
        eager = O.logic op <$> aE <*> bE
     in case (pShortCircuit pol, t, op) of
          -- decision A17: eager by default; the short-circuit alternative skips
          -- the right operand of AND/OR on BOOL when the left one decides
          (ShortCircuit, BOOL, OpAnd) -> aE >>= \x -> if x == VBool False then pure x else O.logic op x <$> bE
          (ShortCircuit, BOOL, OpOr) -> aE >>= \x -> if x == VBool True then pure x else O.logic op x <$> bE
          _ -> eager
  CCall line fid _ args -> compileCall ctx line fid args
  CExpt line _ a b ->
    let aE = compileExpr ctx a
        bE = compileExpr ctx b
     in do
          x <- aE
          y <- bE
          outcome line (O.expt pol x y) -- MT-OP-20
  where
    pol = cxPolicies ctx

-- | A call: arguments left to right (decision A18), then a new frame one
-- level deeper; a 17th nested frame is runtime error 2050 at the line of the
-- call (MT-POU-9, decision A27). The caller's frame comes back afterwards.
compileCall :: Ctx -> Line -> FunId -> [CExpr] -> Exec s Value
compileCall ctx line fid args = case IM.lookup fid (cxFunctions ctx) of
  Nothing -> failWith errMalformed line
  Just (Function fun) ->
    let argsE = traverse (compileExpr ctx) args
     in do
          vs <- argsE
          Exec $ \e m ->
            if envDepth e >= maxCallDepth
              then pure (Failed (runtimeError errCallDepth line)) -- MT-ERR-2050
              else do
                saved <- readSTRef (mFrame m)
                r <- unExec (fun vs) e {envDepth = envDepth e + 1} m
                writeSTRef (mFrame m) saved
                pure r

compileStmt :: Ctx -> CStmt -> Exec s Flow
compileStmt ctx = \case
  SAssign line target e ->
    -- MT-STMT-2: the right side is evaluated before the index of the target
    let eE = compileExpr ctx e
     in case target of
          LTVar v -> step line >> eE >>= writeScalar v >> pure Next
          LTIndex iline v ix ->
            let ixE = compileExpr ctx ix
             in do
                  step line
                  x <- eE
                  k <- ixE >>= elementIndex pol iline v
                  writeElement v k x
                  pure Next
  SCall line fid args ->
    -- MT-STMT-3: the result is discarded
    let callE = compileCall ctx line fid args
     in step line >> callE >> pure Next
  SIf arms elseB ->
    -- MT-STMT-6: the first true test selects its branch, else ELSE
    let armsE = [(l, compileExpr ctx c, compileBlock ctx b) | (l, c, b) <- arms]
        elseE = compileBlock ctx elseB
        firstLine = case arms of
          (l, _, _) : _ -> l
          [] -> 0
        go [] = elseE
        go ((l, cE, bE) : rest) = do
          c <- cE >>= asBool l
          if c then bE else go rest
     in step firstLine >> go armsE
  SCase line sel arms elseB ->
    -- MT-STMT-8: the first arm with a matching value or inclusive range
    let selE = compileExpr ctx sel
        armsE = [(ranges, compileBlock ctx b) | (ranges, b) <- arms]
        elseE = compileBlock ctx elseB
        pick _ [] = elseE
        pick k ((ranges, bE) : rest)
          | any (\(lo, hi) -> lo <= k && k <= hi) ranges = bE
          | otherwise = pick k rest
     in do
          step line
          k <- selE >>= asInteger line
          pick k armsE
  SWhile line c body ->
    -- MT-STMT-13: the test before each iteration
    let cE = compileExpr ctx c
        bodyE = compileBlock ctx body
        loop = do
          step line
          t <- cE >>= asBool line
          if not t
            then pure Next
            else
              bodyE >>= \case
                Next -> loop
                Exiting -> pure Next
                Returning -> pure Returning
     in step line >> loop
  SRepeat body uline c ->
    -- MT-STMT-14: the body first, the loop ends when the test is TRUE
    let cE = compileExpr ctx c
        bodyE = compileBlock ctx body
        loop =
          bodyE >>= \case
            Exiting -> pure Next
            Returning -> pure Returning
            Next -> do
              step uline
              t <- cE >>= asBool uline
              if t then pure Next else loop
     in step uline >> loop
  SFor line cv start end by body -> compileFor ctx line cv start end by body
  SExit line -> step line >> pure Exiting -- MT-STMT-12
  SReturn line -> step line >> pure Returning -- MT-STMT-4, MT-STMT-5
  where
    pol = cxPolicies ctx
    step = tick (pStepBudget pol)

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
compileFor :: Ctx -> Line -> Var -> CExpr -> CExpr -> CExpr -> [CStmt] -> Exec s Flow
compileFor ctx line cv start end by body = do
  step
  readStart >>= writeScalar cv
  case pForBounds pol of
    ForOnce -> do
      e <- readEnd
      s <- readStep
      loop (pure (e, s))
    ForEveryIteration -> loop ((,) <$> readEnd <*> readStep)
  where
    pol = cxPolicies ctx
    step = tick (pStepBudget pol) line
    readStart = compileExpr ctx start
    readEnd = compileExpr ctx end
    readStep = compileExpr ctx by
    bodyE = compileBlock ctx body
    t = varBasicType cv
    intRangeInt = (\(lo, hi) -> (fromInteger lo, fromInteger hi) :: (Int, Int)) <$> intRange t
    loop bounds = go
      where
        go = do
          step
          (e, s) <- bounds
          c <- readScalar cv
          if continues s c e
            then
              bodyE >>= \case
                Exiting -> pure Next
                Returning -> pure Returning
                Next -> increment s >>= \more -> if more then go else pure Next
            else pure Next
    continues s c e
      | numCompare s (defaultValue t) == LT = numCompare c e /= LT
      | otherwise = numCompare c e /= GT
    increment s = do
      c <- readScalar cv
      case pForAtTypeMax pol of
        StopAtEnd -> case (valueToInt c, valueToInt s, intRangeInt) of
          (Just ci, Just si, Just (lo, hi))
            | ci + si < lo || ci + si > hi -> pure False
            | otherwise -> writeScalar cv (integerToValue t (toInteger (ci + si))) >> pure True
          _ -> case (c, s) of
            (VReal x, VReal y) -> writeScalar cv (VReal (x + y)) >> pure True
            _ -> failWith errMalformed line
        FollowOverflowPolicy -> do
          n <- outcome line (O.arith pol OpAdd c s)
          writeScalar cv n
          pure True

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
