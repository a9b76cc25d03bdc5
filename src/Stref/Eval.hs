-- | The meaning of checked expressions and statements (catalogue §§ 5, 6, 8).
--
-- Denotational style: every 'CExpr' and 'CStmt' is translated ONCE into a
-- Haskell closure over the machine state ('Exec'); running a loop runs the
-- closure again, it never walks the tree again. The policies are fixed at
-- translation time, so a closure already is the meaning under one dialect.
--
-- Everything here is pure: the machine state is threaded explicitly, a
-- runtime error is a value that carries the state at the moment it occurred
-- (operand writes made before an error persist, MT-EXEC-8).
module Stref.Eval
  ( -- * The machine
    Machine (..)
  , Env (..)
  , Res (..)
  , Exec (..)
  , runExec
  , failWith
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

import qualified Data.IntMap.Strict as IM
import Data.IntMap.Strict (IntMap)
import Stref.Checked
import Stref.Conversions (convert)
import Stref.Diagnostics
import Stref.Operands
import qualified Stref.Operators as O
import Stref.Policy
import Stref.Types
import Stref.Values

-- | The state one module call works on.
data Machine = Machine
  { mData :: !(IntMap Value) -- ^ the module data area (MT-MAP-1)
  , mFrame :: !(IntMap Value) -- ^ the active function call's frame (MT-SCOPE-7)
  , mMemory :: !Memory -- ^ the PLC operands
  , mOutputs :: !(Bool, Bool, Bool) -- ^ OUTPUT1..3 (MT-SIG-4)
  , mOverflow :: !Bool -- ^ INTERNAL_OVERFLOW (MT-OP-7)
  , mSteps :: !Int -- ^ steps used of the budget (MT-EXEC-7)
  }
  deriving (Eq, Show)

-- | What does not change while a closure runs: the module inputs and the
-- number of active function frames.
data Env = Env
  { envInputs :: !(Bool, Bool, Bool) -- ^ INPUT1..3 (MT-SIG-2)
  , envDepth :: !Int -- ^ active function frames (decision A27)
  }
  deriving (Eq, Show)

-- | The outcome of running a closure: a value and the new state, or a
-- runtime error and the state at the moment of the error.
data Res a
  = Done a !Machine
  | Failed !RuntimeError !Machine

-- | A state and error monad, written out so that it stays small and fast.
newtype Exec a = Exec {unExec :: Env -> Machine -> Res a}

runExec :: Exec a -> Env -> Machine -> Res a
runExec = unExec

instance Functor Exec where
  fmap f (Exec g) = Exec $ \e m -> case g e m of
    Done a m' -> Done (f a) m'
    Failed x m' -> Failed x m'

instance Applicative Exec where
  pure a = Exec $ \_ m -> Done a m
  Exec f <*> Exec g = Exec $ \e m -> case f e m of
    Failed x m' -> Failed x m'
    Done h m' -> case g e m' of
      Failed x m'' -> Failed x m''
      Done a m'' -> Done (h a) m''

instance Monad Exec where
  Exec g >>= k = Exec $ \e m -> case g e m of
    Failed x m' -> Failed x m'
    Done a m' -> unExec (k a) e m'

getsM :: (Machine -> a) -> Exec a
getsM f = Exec $ \_ m -> Done (f m) m

modifyM :: (Machine -> Machine) -> Exec ()
modifyM f = Exec $ \_ m -> Done () (f m)

failWith :: ErrorCode -> Line -> Exec a
failWith c l = Exec $ \_ m -> Failed (runtimeError c l) m

-- | MT-POU-9, MT-LIM-1: at most 16 nested function calls.
maxCallDepth :: Int
maxCallDepth = 16

-- | Reported when the checked program is inconsistent (a value of the wrong
-- type, a missing function): a bug of the checker, never of the ST program.
errMalformed :: ErrorCode
errMalformed = 9999

-- | One step of the budget; exceeding it is runtime error 2030 at the line
-- being executed (MT-EXEC-7).
tick :: Int -> Line -> Exec ()
tick budget line = Exec $ \_ m ->
  let s = mSteps m + 1
   in if s > budget
        then Failed (runtimeError errExecutionTime line) m
        else Done () m {mSteps = s}

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

-- | Read element @off@ (0-based) of a variable; 0 for a scalar. The home
-- is inspected when the closure is built, not when it runs.
readElement :: Var -> Int -> Exec Value
readElement v off = case varHome v of
  Data i -> let k = i + off in Exec $ \_ m -> Done (IM.findWithDefault def k (mData m)) m
  Frame i -> let k = i + off in Exec $ \_ m -> Done (IM.findWithDefault def k (mFrame m)) m
  Mapped o -> let o' = elementOperand o off in Exec $ \_ m -> Done (readOperand (mMemory m) o' t) m
  SignalInput n -> Exec $ \e m -> Done (VBool (signal n (envInputs e))) m
  SignalOutput n -> Exec $ \_ m -> Done (VBool (signal n (mOutputs m))) m
  OverflowFlag -> Exec $ \_ m -> Done (VBool (mOverflow m)) m
  where
    t = varBasicType v
    def = defaultValue t

signal :: Int -> (Bool, Bool, Bool) -> Bool
signal n (a, b, c) = case n of
  1 -> a
  2 -> b
  3 -> c
  _ -> False

setSignal :: Int -> Bool -> (Bool, Bool, Bool) -> (Bool, Bool, Bool)
setSignal n x (a, b, c) = case n of
  1 -> (x, b, c)
  2 -> (a, x, c)
  3 -> (a, b, x)
  _ -> (a, b, c)

readScalar :: Var -> Exec Value
readScalar v = readElement v 0

-- | Write element @off@ of a variable. INPUTn are read-only (MT-SIG-2); the
-- checker never produces such a write, and it is ignored here.
writeElement :: Var -> Int -> Value -> Exec ()
writeElement v off = case varHome v of
  Data i -> let k = i + off in \x -> modifyM $ \m -> m {mData = IM.insert k x (mData m)}
  Frame i -> let k = i + off in \x -> modifyM $ \m -> m {mFrame = IM.insert k x (mFrame m)}
  Mapped o -> let o' = elementOperand o off in \x -> modifyM $ \m -> m {mMemory = writeOperand o' x (mMemory m)}
  SignalInput _ -> \_ -> pure ()
  SignalOutput n -> \x -> modifyM $ \m -> m {mOutputs = setSignal n (boolOf x) (mOutputs m)}
  OverflowFlag -> \x -> modifyM $ \m -> m {mOverflow = boolOf x}
  where
    boolOf = \case
      VBool b -> b
      _ -> False

writeScalar :: Var -> Value -> Exec ()
writeScalar v = writeElement v 0

-- | Give a variable its initial value (MT-VAR-3, MT-VAR-4, MT-ARR-6): the
-- initialiser, or the type default; a mapped variable without initialiser
-- is left alone (MT-VAR-3, MT-MAP-4 b), one with an initialiser is written
-- (decision A3, MT-MAP-15).
initVar :: VarInit -> Exec ()
initVar (VarInit v ini) = case (varHome v, ini) of
  (Mapped _, Nothing) -> pure ()
  (_, Nothing) -> mapM_ (\k -> writeElement v k def) [0 .. varElements v - 1]
  (_, Just (InitScalar x)) -> mapM_ (\k -> writeElement v k x) [0 .. varElements v - 1]
  (_, Just (InitArray xs)) -> mapM_ (uncurry (writeElement v)) (zip [0 .. varElements v - 1] xs)
  where
    def = defaultValue (varBasicType v)

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
  { cmBody :: Exec Flow
  , cmFunctionMeanings :: IntMap ([Value] -> Exec Value)
  }

data Ctx = Ctx
  { cxPolicies :: Policies
  , cxFunctions :: IntMap ([Value] -> Exec Value)
  }

-- | Translate the whole module once. Functions refer to each other through
-- the lazily built table of meanings (a knot: each function is translated
-- once, however often it is called).
compileModule :: Policies -> CModule -> CompiledModule
compileModule pol cm = CompiledModule body funs
  where
    ctx = Ctx pol funs
    funs = IM.map (compileFunction ctx) (cmFunctions cm)
    body = compileBlock ctx (cpBody (cmProgram cm))

-- | A function call in a fresh frame (MT-SCOPE-7): the result slot starts
-- at its type default, the parameters take the arguments in declaration
-- order (MT-POU-5), the locals their initial values; the result is the
-- result slot when the body ends or returns (MT-POU-4, MT-STMT-4).
compileFunction :: Ctx -> CFunction -> [Value] -> Exec Value
compileFunction ctx f = \args -> do
  modifyM $ \m -> m {mFrame = IM.singleton 0 (defaultValue (cfResult f))}
  mapM_ (uncurry writeScalar) (zip (cfParams f) args)
  mapM_ initVar (cfLocals f)
  _ <- body
  getsM (IM.findWithDefault (defaultValue (cfResult f)) 0 . mFrame)
  where
    body = compileBlock ctx (cfBody f)

-- | A statement list: stops at the first EXIT or RETURN.
compileBlock :: Ctx -> [CStmt] -> Exec Flow
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
outcome :: Line -> O.Outcome -> Exec Value
outcome line = \case
  Left code -> failWith code line
  Right (v, flag) -> do
    case flag of
      Just b -> modifyM (\m -> m {mOverflow = b})
      Nothing -> pure ()
    pure v

asBool :: Line -> Value -> Exec Bool
asBool line = \case
  VBool b -> pure b
  _ -> failWith errMalformed line

asInteger :: Line -> Value -> Exec Integer
asInteger line v = maybe (failWith errMalformed line) pure (valueToInteger v)

-- | The 0-based element of an array for an index value, under the
-- @index-out-of-range@ policy (MT-ARR-2, MT-ARR-8, decision A23).
elementIndex :: Policies -> Line -> Var -> Value -> Exec Int
elementIndex pol line v iv = do
  k <- asInteger line iv
  case varType v of
    Basic _ -> failWith errMalformed line
    Array lo hi _
      | k >= lo && k <= hi -> pure (fromInteger (k - lo))
      | otherwise -> case pIndexOutOfRange pol of
          IndexError -> failWith errIndex line -- MT-ERR-2015
          IndexTrap -> failWith trapIndex line
          IndexClamp -> pure (fromInteger (max lo (min hi k) - lo))

compileExpr :: Ctx -> CExpr -> Exec Value
compileExpr ctx = \case
  CLit v -> pure v
  CRead v -> readScalar v
  CReadIndex line v ix ->
    let ixE = compileExpr ctx ix
     in ixE >>= elementIndex pol line v >>= readElement v
  CConv from to e ->
    let eE = compileExpr ctx e
     in convert pol from to <$> eE -- MT-CONV-5
  CNeg line _ e ->
    let eE = compileExpr ctx e
     in eE >>= outcome line . O.negateValue pol -- MT-OP-4, MT-OP-6
  CNot _ e -> O.notValue <$> compileExpr ctx e -- MT-OP-14
  CArith line op _ a b ->
    let aE = compileExpr ctx a
        bE = compileExpr ctx b
     in do
          x <- aE
          y <- bE
          outcome line (O.arith pol op x y)
  CCompare op _ a b -> O.compareValues op <$> compileExpr ctx a <*> compileExpr ctx b >>= pure . VBool
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
compileCall :: Ctx -> Line -> FunId -> [CExpr] -> Exec Value
compileCall ctx line fid args = case IM.lookup fid (cxFunctions ctx) of
  Nothing -> failWith errMalformed line
  Just fun ->
    let argsE = traverse (compileExpr ctx) args
     in do
          vs <- argsE
          Exec $ \e m ->
            if envDepth e >= maxCallDepth
              then Failed (runtimeError errCallDepth line) m -- MT-ERR-2050
              else
                let saved = mFrame m
                    e' = e {envDepth = envDepth e + 1}
                 in case unExec (fun vs) e' m of
                      Done v m' -> Done v m' {mFrame = saved}
                      Failed x m' -> Failed x m' {mFrame = saved}

compileStmt :: Ctx -> CStmt -> Exec Flow
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
compileFor :: Ctx -> Line -> Var -> CExpr -> CExpr -> CExpr -> [CStmt] -> Exec Flow
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
        StopAtEnd -> case (valueToInteger c, valueToInteger s, intRange t) of
          (Just ci, Just si, Just (lo, hi))
            | ci + si < lo || ci + si > hi -> pure False
            | otherwise -> writeScalar cv (integerToValue t (ci + si)) >> pure True
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
numCompare a b = case (valueToInteger a, valueToInteger b, a, b) of
  (Just x, Just y, _, _) -> compare x y
  (_, _, VReal x, VReal y)
    | x < y -> LT
    | x > y -> GT
    | otherwise -> EQ
  _ -> EQ
