-- | The meaning of IEC statements, expressions and POU calls: the readable,
-- definitional evaluator. One function per construct, each taking the
-- policy record; the state is a tree of values (globals, program instances,
-- function frames) and the bytes of the located variables.
module Stref.IEC.Eval
  ( Machine (..)
  , initialMachine
  , runCycle
  , initialize
  , readVariablePath
  , writeVariablePath
  , readLocatedVar
  , layoutOf
  , writeLocatedVar
  , Stop (..)
  , ResetEvent (..)
  , resetEvents
  , resetMachine
  , restart
    -- * Tracing
  , startTrace
  , traceCycle
  , traceOf
    -- * Shared with the fast evaluator ("Stref.IEC.Fast")
  , MemoryMap (..)
  , memoryMap
  , watchdogFault
  , fitWhy
  , indexWhy
  , intValue
  , convertValue
  , checkDivName
  , ordinal
  , asBool
  , forDefaultStep
  , forGoesOn
  , forIncrement
  ) where

import Control.Monad (forM, forM_, guard, unless, when)
import Control.Monad.Except (ExceptT, catchError, runExceptT, throwError)
import Control.Monad.Reader (ReaderT, ask, asks, local, runReaderT)
import Control.Monad.State.Strict (State, gets, modify', runState)
import Data.Char (chr, ord)
import Data.Bits (clearBit, setBit, shiftL, shiftR, testBit, (.&.))
import Data.Foldable (toList)
import Data.List (find)
import qualified Data.Map.Strict as M
import Data.Maybe (fromMaybe, isJust)
import qualified Data.Sequence as Seq
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word8)
import Numeric (showHex)
import GHC.Float (float2Double, castDoubleToWord64, castFloatToWord32, castWord32ToFloat, castWord64ToDouble)
import Stref.IEC.Checked
import Stref.IEC.Conversions (convert, isConversionName, truncTo)
import Stref.IEC.Memory (Layout (..), layout, remembering, areaAt, areaBase, decode, encode, frameBase, globalsBase, leafAt, locate, offsetOf, placeAll, plainData, programsBase, setUnionMember, sizeInBytes, unionMember)
import Stref.IEC.Operators (binary, binaryOverflows, binaryWhy, unary, unaryOverflows, wrapUnder)
import Stref.IEC.Standard (standard, timeFunction)
import Stref.IEC.Syntax (AssignOp (..), BinOp (..), binOpSymbol, EdgeQualifier (..), Location (..), Pos (..), PouKind (..), Section (..), byteSized)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Stref.Trace

-- | The controller's state between and during cycles.
-- The maps are strict fields, so that a long cycle (millions of steps up to
-- the budget) leaves no chain of pending updates behind.
data Machine = Machine
  { mGlobals :: !(M.Map Text Value)
  , mPrograms :: !(M.Map Text Value) -- ^ program instances by key
  , mFrames :: !(M.Map Int Value) -- ^ function frames by call depth
  , mMemory :: !(M.Map (Char, Integer) Integer) -- ^ located bytes by area and address
  , mClock :: !Integer -- ^ the virtual clock, milliseconds
  , mSteps :: !Int -- ^ statements and loop tests executed in this cycle
  , mTrace :: Maybe Tracer -- ^ the events of a traced run (docs/trace.md); Nothing: not traced
  }
  deriving (Eq, Show)

-- | How a cycle ended early.
data Stop = StopFault Pos Fault
  deriving (Eq, Show)

data Signal = SigExit | SigReturn | SigContinue | SigJump Text | SigFault Pos Fault

data Ctx = Ctx
  { cxPol :: Policies
  , cxProgram :: Program
  , cxSelf :: RefPath -- ^ the running POU's instance or frame
  , cxThis :: RefPath -- ^ the instance its code runs on (a method's: NX-POU-27)
  , cxChecked :: Bool -- ^ do the implicit check functions apply here (NX-ERR-3, NX-ERR-4)
  , cxWriting :: Bool -- ^ is the reference being resolved written (CheckPointer's bWrite, NX-ERR-19)
  , cxDepth :: Int
  , cxNames :: M.Map Text Text -- ^ the variables' names as declared, by key: for the trace (built only when used)
  , cxMemory :: MemoryMap -- ^ the layout and where the globals and program instances lie (built once, when used)
  }

-- | The context a cycle or an initialisation starts in.
topContext :: Policies -> Program -> Ctx
topContext pol prog = Ctx pol prog (RefPath (RootProgram "") []) (RefPath (RootProgram "") []) True False 0 (declaredNames prog) (memoryMap prog)

type Eval = ReaderT Ctx (ExceptT Signal (State Machine))


-- | The state before the first cycle: every variable at its initial value
-- (TC-VAR-35, TC-VAR-36), located variables with initial values written.
initialMachine :: Program -> Machine
initialMachine prog =
  let globals = M.fromList [(viKey v, viInit v) | v <- prGlobals prog, viAt v == Nothing]
      programs = M.fromList [(key inst, instanceOf t) | (inst, t) <- prRoots prog]
      instanceOf t = case lookupPou prog t of
        Just d -> VInstance (pdName d) (M.fromList [(viKey v, viInit v) | v <- pdVars d])
        Nothing -> VInstance t M.empty
      located =
        [(l, viType v, viInit v) | v <- prGlobals prog, Just l <- [viAt v]]
          ++ [(l, viType v, viInit v) | (_, t) <- prRoots prog, Just d <- [lookupPou prog t], v <- pdVars d, Just l <- [viAt v]]
      -- only explicit initial values: a default must not overwrite the
      -- initial value of another variable at the same bytes
      memory = foldl (\m (l, t, v) -> writeLocated l t v m) M.empty [x | x@(_, t, v) <- located, v /= defaultValue t]
   in Machine globals programs M.empty memory 0 0 Nothing

-- | The controller's resets of Table 4-4 (NX-VAR-21, NX-VAR-22).
data ResetEvent = WarmReset | ColdReset | OriginReset | Download
  deriving (Eq, Show)

-- | Their names in a case's calls (docs/nexto.md).
resetEvents :: [(Text, ResetEvent)]
resetEvents = [("warm", WarmReset), ("cold", ColdReset), ("origin", OriginReset), ("download", Download)]

-- | A reset between cycles: every variable takes its initial value again
-- unless its retention keeps it over this event (Table 4-4): RETAIN over
-- a warm reset, PERSISTENT over warm and cold resets and a download; a
-- no_init variable over warm and cold resets (NX-PRAGMA-9, NX-VAR-30).
-- Inside an instance each variable is kept or not by its own declaration
-- (NX-VAR-23); an instance declared RETAIN keeps all of it.
resetMachine :: ResetEvent -> Program -> Machine -> Machine
resetMachine ev prog m =
  m
    { mGlobals = M.mapWithKey (\k v -> maybe v (`resetVar` v) (find ((== k) . viKey) (prGlobals prog))) (mGlobals m)
    , mPrograms = M.map resetInstance (mPrograms m)
    , mFrames = M.empty
    }
  where
    resetVar vi v
      | keptOver ev (viRetention vi) = v
      | otherwise = case v of
          VInstance {} -> resetInstance v
          _ -> viInit vi
    resetInstance = \case
      VInstance t fs | Just d <- lookupPou prog t ->
        VInstance t (M.mapWithKey (\k x -> maybe x (`resetVar` x) (varByKey d k)) fs)
      v -> v

-- | Table 4-4: does a variable of this retention keep its value over the event?
keptOver :: ResetEvent -> Retention -> Bool
keptOver ev = \case
  Volatile -> False
  RetainOverWarm -> ev == WarmReset
  Persistent -> ev `elem` [WarmReset, ColdReset, Download]
  NoInit -> ev `elem` [WarmReset, ColdReset]

-- | A reset of the controller between cycles: every FB instance's FB_Exit
-- (NX-POU-35), the values of Table 4-4 (resetMachine), then the
-- initialisation of a start again, which calls every FB_Init.
restart :: Policies -> Program -> ResetEvent -> Machine -> (Machine, Maybe Stop)
restart pol prog ev m0 =
  let (m1, exitStop) = runInit pol prog m0 (everyInstance prog fbExit)
      (m2, initStop) = initialize pol prog (Just ev) (resetMachine ev prog m1)
   in (m2, maybe initStop Just exitStop)

-- | NX-VAR-24..28: the initial values computed when the controller
-- starts, after the constant ones: the globals' (list by list), then every
-- program instance's and, inside it, every FB instance's, each in
-- declaration order. After a reset, the variables the reset kept keep
-- their values. NX-POU-35: once an instance is initialised, with the
-- instances it contains, its FB_Init runs, the base FB's first (NX-POU-44).
initialize :: Policies -> Program -> Maybe ResetEvent -> Machine -> (Machine, Maybe Stop)
initialize pol prog ev m0 = runInit pol prog m0 $ do
  forM_ (prGlobalInits prog) $ \(k, t, ce) ->
    unless (kept (fmap viRetention (find ((== k) . viKey) (prGlobals prog)))) $
      eval ce >>= storePath (cePos ce) t (RefPath (RootGlobal k) [])
  forM_ [(v, fb) | v <- prGlobals prog, TFB fb <- [viType v]] $ \(v, fb) -> do
    args <- evalArgs (M.findWithDefault [] (viKey v) (prGlobalInitArgs prog))
    instanceInits (RefPath (RootGlobal (viKey v)) []) fb (kept (Just (viRetention v))) args
  forM_ (prRoots prog) $ \(inst, t) -> instanceInits (RefPath (RootProgram (key inst)) []) t False []
  where
    kept = maybe False (\r -> maybe False (`keptOver` r) ev)
    evalArgs = mapM (\(k, e) -> (k,) <$> eval e)
    instanceInits path t wholeKept args = case lookupPou prog t of
      Just d -> local (\c -> c {cxSelf = path, cxThis = path}) $ do
        unless wholeKept $
          forM_ (pdInits d) $ \(k, ty, ce) ->
            unless (kept (viRetention <$> varByKey d k)) $ eval ce >>= storePath (cePos ce) ty (extend path (StepField k))
        forM_ [(v, fb) | v <- pdVars d, TFB fb <- [viType v]] $ \(v, fb) -> do
          inner <- evalArgs (M.findWithDefault [] (viKey v) (pdInitArgs d))
          instanceInits (extend path (StepField (viKey v))) fb (wholeKept || kept (Just (viRetention v))) inner
        when (pdKind d == KFunctionBlock) (fbInit path d args)
      Nothing -> pure ()
    -- bInitRetains: are the retentive variables initialised by this start?
    fbInit path d args =
      forM_ (reverse (lineage prog d)) $ \level -> case M.lookup "FB_INIT" (pdMethods level) of
        Just md ->
          let given = [("BINITRETAINS", VBool (ev /= Just WarmReset)), ("BINCOPYCODE", VBool False)] ++ args
           in () <$ callFunctionWith (pdEndPos md) md (Just path) [(k, v) | (k, v) <- given, isJust (varByKey md k)] [] []
        Nothing -> pure ()

-- | NX-POU-35, NX-POU-44: an instance's FB_Exit before a reset, the derived
-- FB's first.
fbExit :: RefPath -> PouDef -> Eval ()
fbExit path d = do
  prog <- asks cxProgram
  forM_ (lineage prog d) $ \level -> case M.lookup "FB_EXIT" (pdMethods level) of
    Just md -> () <$ callFunctionWith (pdEndPos md) md (Just path) [(k, v) | (k, v) <- [("BINCOPYCODE", VBool False)], isJust (varByKey md k)] [] []
    Nothing -> pure ()

-- | An FB type and the FBs it extends, the type itself first.
lineage :: Program -> PouDef -> [PouDef]
lineage prog = go (16 :: Int)
  where
    go 0 _ = []
    go n d = d : maybe [] (go (n - 1)) (pdBase d >>= lookupPou prog)

-- | Every FB instance of the globals and the program instances, outer
-- instances before those they contain, each in declaration order.
everyInstance :: Program -> (RefPath -> PouDef -> Eval ()) -> Eval ()
everyInstance prog act = do
  forM_ [(v, fb) | v <- prGlobals prog, TFB fb <- [viType v]] $ \(v, fb) -> visit (RefPath (RootGlobal (viKey v)) []) fb
  forM_ (prRoots prog) $ \(inst, t) -> visit (RefPath (RootProgram (key inst)) []) t
  where
    visit path t = case lookupPou prog t of
      Just d -> local (\c -> c {cxSelf = path, cxThis = path}) $ do
        when (pdKind d == KFunctionBlock) (act path d)
        forM_ [(v, fb) | v <- pdVars d, TFB fb <- [viType v]] $ \(v, fb) -> visit (extend path (StepField (viKey v))) fb
      Nothing -> pure ()

-- | Run initialisation code outside a cycle.
runInit :: Policies -> Program -> Machine -> Eval () -> (Machine, Maybe Stop)
runInit pol prog m0 act =
  let ctx = topContext pol prog
      (r, m) = runState (runExceptT (runReaderT act ctx)) m0 {mSteps = 0, mFrames = M.empty}
   in case r of
        Left (SigFault p f) -> (m, Just (StopFault p f))
        _ -> (m, Nothing)

-- | One scan cycle at the given clock: each program instance in order.
-- NX-VAR-15: the variables VAR_CONFIG places take their inputs before the
-- task and give their outputs to the process image only after it, when it
-- ends without an error.
runCycle :: Policies -> Program -> Integer -> Machine -> (Machine, Maybe Stop)
runCycle pol prog clock m0 =
  let inputs m1 = foldl (\acc (_, steps, l, t) -> fromMaybe acc (writeVariablePath prog acc steps (readLocated (prTimeRange prog) l t (mMemory acc)))) m1 [c | c@('I', _, _, _) <- prVarConfig prog]
      outputs m1 = foldl (\acc (_, steps, l, t) -> maybe acc (\(v, _) -> acc {mMemory = writeLocated l t v (mMemory acc)}) (readVariablePath prog acc steps)) m1 [c | c@('Q', _, _, _) <- prVarConfig prog]
      m = inputs m0 {mClock = clock, mSteps = 0, mFrames = M.empty}
      -- TC-CFG-9, NX-TASK-1 (open: the IEC task model): a periodic task's
      -- programs run in the cycle where its interval comes round on the
      -- virtual clock (at 0, I, 2I, ...); the others in every cycle
      due inst = case M.lookup (key inst) (prPeriods prog) of
        Just period | period > 0 -> clock == 0 || clock `div` period > mClock m0 `div` period
        _ -> True
      run = forM_ [(inst, t) | (inst, t) <- prInstances prog, due inst] $ \(inst, t) -> case lookupPou prog t of
        Just d -> let here = RefPath (RootProgram (key inst)) [] in local (\c -> c {cxSelf = here, cxThis = here}) (callBody d)
        Nothing -> pure ()
      ctx = topContext pol prog
      (r, m') = runState (runExceptT (runReaderT run ctx)) m
   in case r of
        Left (SigFault p f) -> (traceFault pol p f m', Just (StopFault p f))
        _ -> (outputs m', Nothing)

------------------------------------------------------------------------------
-- Tracing (docs/trace.md): events emitted where the meaning functions
-- decide; without a tracer nothing is built

-- | A machine whose runs are traced from now on; with @True@ every
-- iteration of every loop is kept.
startTrace :: Bool -> Machine -> Machine
startTrace every m = m {mTrace = Just (newTracer every)}

-- | Mark the start of a cycle in the trace.
traceCycle :: Int -> Machine -> Machine
traceCycle k m = m {mTrace = emit (Cycle k) <$> mTrace m}

-- | The trace so far, oldest event first.
traceOf :: Machine -> [Event]
traceOf = maybe [] tracerEvents . mTrace

-- | Emit an event, when the run is traced.
note :: Event -> Eval ()
note ev = noteWith (const ev)
{-# INLINE note #-}

-- | Emit an event that names variables, when the run is traced.
noteWith :: (Ctx -> Event) -> Eval ()
noteWith ev = do
  t <- gets mTrace
  case t of
    Nothing -> pure ()
    Just tr -> do
      c <- ask
      modify' (\m -> m {mTrace = Just (emit (ev c) tr)})
{-# INLINE noteWith #-}

tracing :: Eval Bool
tracing = gets (isJust . mTrace)

-- | An action, then, when the run is traced, the event its result makes.
-- Untraced, the action is all that runs, with nothing bound after it (for
-- the most frequent events: reads, writes, statements).
noting :: (Ctx -> a -> Event) -> Eval a -> Eval a
noting ev act = do
  on <- tracing
  if on then act >>= \x -> x <$ noteWith (`ev` x) else act
{-# INLINE noting #-}

-- | A statement, told when it is done.
statement :: Pos -> Eval () -> Eval ()
statement p = noting (\_ _ -> Statement (posLine p))
{-# INLINE statement #-}

-- | A runtime error in the trace, with the rule that makes it one.
traceFault :: Policies -> Pos -> Fault -> Machine -> Machine
traceFault pol p f m = m {mTrace = emit (Failure (posLine p) rule (faultMessage f)) <$> mTrace m}
  where
    -- (not again when the message cites it already)
    rule = case citedRules pol (decision (faultRules (faultKind f)) "") of
      r : _ | not (r `T.isInfixOf` faultMessage f) -> Just r
      _ -> Nothing

-- | The rules behind each kind of runtime error, in both IEC catalogues.
faultRules :: Text -> [Text]
faultRules = \case
  "watchdog" -> ["TC-ERR-1", "NX-ERR-26"]
  "division-by-zero" -> ["TC-OP-22", "NX-OP-29"]
  "index-out-of-range" -> ["TC-ERR-3", "NX-ERR-9"]
  -- NX-TYPE-70: a value outside the subrange is an error (NX-ERR-17 is the
  -- unchecked alternative's)
  "subrange" -> ["TC-TYPE-33", "NX-TYPE-70"]
  "overflow" -> ["TC-OP-20", "NX-OP-32"]
  "null-pointer" -> ["NX-ERR-21"]
  "conversion" -> ["TC-CONV-12", "NX-ERR-22"]
  "call-depth" -> ["TC-ERR-6"]
  _ -> []

-- | A variable's name as the trace shows it: the steps from the program,
-- frame or global it lies in, with the names as declared.
pathName :: M.Map Text Text -> RefPath -> Text
pathName names (RefPath root steps) = case root of
  RootGlobal k -> named k <> T.concat (map stepText steps)
  RootLocated t -> t <> T.concat (map stepText steps)
  RootBytes area a _ -> "%" <> T.singleton area <> "B" <> T.pack (show a) <> T.concat (map stepText steps)
  RootAt a _ -> "16#" <> T.pack (showHex a "") <> "^" <> T.concat (map stepText steps)
  RootProgram k | null steps -> k
  _ -> T.drop 1 (T.concat (map stepText steps))
  where
    named k = M.findWithDefault k k names
    stepText = \case
      StepField f -> "." <> named f
      StepIndex is -> "[" <> T.intercalate "," (map (T.pack . show) is) <> "]"
      StepBit i -> "." <> T.pack (show i)
      StepChar _ i -> "[" <> T.pack (show i) <> "]"

-- | The name of a reference's variable in the trace.
refName :: Ctx -> CRef -> RefPath -> Text
refName c r path = case r of
  CLocated l _ -> locText l
  _ -> pathName (cxNames c) path

-- | Run iteration @k@ of a loop; when tracing, it is told, and RETURN or
-- JMP leaving the loop first closes it in the trace (an error ends the
-- cycle, and the trace shows it as the error).
iteration :: Int -> Int -> Eval a -> Eval a
iteration l k act = do
  on <- tracing
  let closing e = case e of
        SigFault {} -> throwError e
        _ -> note (LoopExit l k) >> throwError e
  if on then note (Iteration l k) >> (act `catchError` closing) else act

fault :: Pos -> Fault -> Eval a
fault p f = throwError (SigFault p f)

orFault :: Pos -> Either Fault a -> Eval a
orFault p = either (fault p) pure

-- | One step of the watchdog's budget (TC-ERR-1, TC-STMT-34).
tick :: Pos -> Eval ()
tick p = do
  budget <- asks (pStepBudget . cxPol)
  n <- gets mSteps
  when (n >= budget) $ asks cxPol >>= \pol -> fault p (watchdogFault pol budget)
  modify' (\m -> m {mSteps = n + 1})

-- | MT-EXEC-7 (error 2030): a MasterTool module's budget counts a loop
-- statement once on entering it, besides its tests (the count of the
-- MasterTool modules, Stref.Eval); an IEC cycle counts the tests only.
-- REPEAT's step is at its UNTIL, where its tests are.
loopEntry :: Pos -> Eval ()
loopEntry p = do
  pol <- asks cxPol
  when (pSourceForm pol == MasterToolSource) (tick p)

-- | The position of a REPEAT's test: its UNTIL under MasterTool (MT-EXEC-7,
-- as 'loopEntry'), the REPEAT's own otherwise.
repeatTestPos :: Pos -> CExpr -> Eval Pos
repeatTestPos p c = do
  pol <- asks cxPol
  pure (if pSourceForm pol == MasterToolSource then cePos c else p)

-- | The watchdog's error when the cycle exceeds its budget of steps.
watchdogFault :: Policies -> Int -> Fault
watchdogFault pol budget = Fault "watchdog" ("the cycle ran more than " <> T.pack (show budget) <> " steps: the watchdog ends it (cycle error, " <> T.intercalate ", " (citedIds pol (faultRules "watchdog")) <> ")")

------------------------------------------------------------------------------
-- POU calls

-- | Run a POU's body in the current context: VAR_TEMP starts afresh
-- (TC-VAR-8); RETURN ends the body (TC-STMT-38).
callBody :: PouDef -> Eval ()
callBody d = local (\c -> c {cxChecked = pdChecked d}) $ do
  self <- asks cxSelf
  forM_ [v | v <- pdVars d, viSection v == SecTemp] $ \v -> putPath (extend self (StepField (viKey v))) (viInit v)
  levels <- edgesIn d self
  case pdBody d of
    Statements ss -> execBlock ss `catchError` \case
      SigReturn -> pure ()
      SigExit -> pure ()
      e -> throwError e
    Native f -> do
      pol <- asks cxPol
      clock <- gets mClock
      inst <- getPath self
      case inst of
        VInstance n vars -> putPath self (VInstance n (f pol clock vars))
        _ -> pure ()
  mapM_ (uncurry putPath) levels

extend :: RefPath -> Step -> RefPath
extend (RefPath r steps) s = RefPath r (steps ++ [s])

-- | An FB call (TC-POU-33..36): inputs written (unassigned ones keep their
-- values, TC-POU-35), in-outs bound, the body run on the instance, then the
-- outputs copied to their @=>@ targets.
callFB :: Pos -> FBCall -> Eval ()
callFB p c = do
  prog <- asks cxProgram
  d <- maybe (fault p (Fault "call-depth" ("unknown function block " <> fcType c))) pure (lookupPou prog (fcType c))
  inputs <- forM (fcInputs c) $ \(k, e) -> (k,) <$> eval e
  inouts <- forM (fcInOuts c) $ \(k, r) -> (k,r,) <$> refPath p r
  inst <- refPath p (fcInstance c)
  forM_ inputs $ \(k, v) -> storePath p (paramType d k) (extend inst (StepField k)) v
  bindInOuts inst inouts
  depth <- asks cxDepth
  callDepthLimit p depth
  names <- asks cxNames
  let callee = pathName names inst <> " : " <> pdName d
  note (Call (posLine p) callee [(M.findWithDefault k k names, renderValue v) | (k, v) <- inputs])
  local (\cx -> cx {cxSelf = inst, cxThis = inst, cxDepth = depth + 1}) (callBody d)
  on <- tracing
  when on $ do
    outs <- forM [v | v <- pdVars d, viSection v == SecOutput] $ \v -> (viName v,) . renderValue <$> getPath (extend inst (StepField (viKey v)))
    note (Return (posLine p) callee outs)
  copyBack inst inouts
  copyOutputs p inst (fcOutputs c)

-- | The @out => v@ bindings of a call, copied from the called POU's
-- instance or frame after its body (TC-POU-38, NX-POU-13, NX-POU-30).
copyOutputs :: Pos -> RefPath -> [(Text, CRef, Type)] -> Eval ()
copyOutputs p callee outs = forM_ outs $ \(k, r, t) -> do
  v <- getPath (extend callee (StepField k))
  target <- refPath p r
  storeTarget p t r target v

paramType :: PouDef -> Text -> Type
paramType d k = maybe (TElem BOOL) viType (varByKey d k)

-- | R_EDGE / F_EDGE inputs (TC-POU-29): during the body the input reads as
-- the output of an implicit R_TRIG / F_TRIG fed with the input's value
-- (however it was set: by the call, by an assignment from outside, by its
-- initial value); after the body the input holds that value again, so that
-- an input not given at the next call keeps it (TC-POU-35). Returns what to
-- put back.
edgesIn :: PouDef -> RefPath -> Eval [(RefPath, Value)]
edgesIn d inst = do
  pol <- asks cxPol
  forM [(v, q) | v <- pdVars d, Just q <- [viEdge v]] $ \(v, q) -> do
    let field = extend inst (StepField (viKey v))
        memField = extend inst (StepField (viKey v <> "$M"))
    raw <- getPath field
    m <- asBool <$> getPathOr memField (VBool (q == FEdge && pFTrigInitial pol == FTrigTrue))
    let level = asBool raw
        (out, m') = case q of
          REdge -> (level && not m, level) -- TC-FB-16
          FEdge -> (not level && not m, not level) -- TC-FB-15
    putPath memField (VBool m')
    putPath field (VBool out)
    pure (field, raw)

-- | VAR_IN_OUT (TC-VAR-3, TC-VAR-4): the parameter refers to the caller's
-- variable; a located variable (which lives in bytes, not in the tree of
-- values) is copied in and, after the body, back.
bindInOuts :: RefPath -> [(Text, CRef, RefPath)] -> Eval ()
bindInOuts base = mapM_ $ \(k, r, path) -> case r of
  CLocated l t -> located l t >>= putPath (extend base (StepField k))
  _ -> putPath (extend base (StepField k)) (VRef path)

copyBack :: RefPath -> [(Text, CRef, RefPath)] -> Eval ()
copyBack base = mapM_ $ \(k, r, _) -> case r of
  CLocated l t -> do
    v <- getPath (extend base (StepField k))
    modify' (\m -> m {mMemory = writeLocated l t v (mMemory m)})
  _ -> pure ()

asBool :: Value -> Bool
asBool = \case
  VBool b -> b
  _ -> False

-- | A function call (TC-POU-5, TC-POU-6): a fresh frame with the initial
-- values (inputs not given keep their defaults, TC-POU-9), the body, the
-- value of the variable named like the function (TC-STMT-8; unassigned: the
-- type's default, TC-STMT-40).
callFunction :: Pos -> Text -> [(Text, CExpr)] -> [(Text, CRef)] -> [(Text, CRef, Type)] -> Eval Value
callFunction p f ins inouts outs = do
  prog <- asks cxProgram
  d <- maybe (fault p (Fault "call-depth" ("unknown function " <> f))) pure (lookupPou prog f)
  inputs <- forM ins $ \(k, e) -> (k,) <$> eval e
  refs <- forM inouts $ \(k, r) -> (k,r,) <$> refPath p r
  callFunctionWith p d Nothing inputs refs outs

-- | A POU run in a fresh frame: a function, or a method with the instance
-- it runs on (NX-POU-26, NX-POU-27); its result is the variable named like it.
callFunctionWith :: Pos -> PouDef -> Maybe RefPath -> [(Text, Value)] -> [(Text, CRef, RefPath)] -> [(Text, CRef, Type)] -> Eval Value
callFunctionWith p d this inputs refs outs = do
  depth <- asks cxDepth
  callDepthLimit p depth
  let frame = RefPath (RootFrame (depth + 1)) []
  modify' (\m -> m {mFrames = M.insert (depth + 1) (VInstance (pdName d) (M.fromList [(viKey v, viInit v) | v <- pdVars d])) (mFrames m)})
  forM_ inputs $ \(k, v) -> storePath p (paramType d k) (extend frame (StepField k)) v
  bindInOuts frame refs
  noteWith (\c -> Call (posLine p) (pdName d) [(M.findWithDefault k k (cxNames c), renderValue v) | (k, v) <- inputs])
  local (\cx -> cx {cxSelf = frame, cxThis = fromMaybe (cxThis cx) this, cxDepth = depth + 1}) (callBody d)
  copyBack frame refs
  -- NX-POU-13: the outputs bound with => are copied after the body
  copyOutputs p frame outs
  result <- getPath (extend frame (StepField (key (pdName d))))
  note (Return (posLine p) (pdName d) [(pdName d, renderValue result)])
  modify' (\m -> m {mFrames = M.delete (depth + 1) (mFrames m)})
  pure result

-- | NX-ERR-1..20: an implicit check function, called with these values
-- for its inputs in the order of their declaration, when the program
-- declares it and the running POU is checked; Nothing otherwise.
implicitCheck :: Pos -> Text -> [Value] -> Eval (Maybe Value)
implicitCheck p name args = do
  checked <- asks cxChecked
  prog <- asks cxProgram
  -- the declared check functions asked first: most programs declare none
  case (checked && name `elem` prChecks prog, lookupPou prog name) of
    (True, Just d) -> do
      pol <- asks cxPol
      let params = [v | v <- pdVars d, viSection v == SecInput]
      inputs <- forM (zip params args) $ \(v, a) -> (viKey v,) <$> orFault p (convertValue pol (viType v) a)
      Just <$> callFunctionWith p d Nothing inputs [] []
    _ -> pure Nothing

-- | A value converted to a type, as an implicit conversion would.
convertValue :: Policies -> Type -> Value -> Either Fault Value
convertValue pol t v = case (t, v) of
  (TPointer _, VInt _ _) -> Right v
  _ -> case valueElem v of
    Just e | TElem e /= t, Just _ <- baseElem t -> convert pol (TElem e) t v
    _ -> Right v

------------------------------------------------------------------------------
-- Statements (TC-STMT-*)

-- | A block of statements; a JMP to one of its labels (from it or from a
-- block inside it) goes on from that label (NX-STMT-42).
execBlock :: [CStmt] -> Eval ()
execBlock ss
  | any isLabel ss = run ss
  | otherwise = mapM_ exec ss
  where
    isLabel = \case
      CLabel {} -> True
      _ -> False
    run xs = mapM_ exec xs `catchError` \case
      SigJump l | Just rest <- from l -> run rest
      e -> throwError e
    from l = case break (\case CLabel _ l' -> l' == l; _ -> False) ss of
      (_, []) -> Nothing
      (_, rest) -> Just rest

exec :: CStmt -> Eval ()
exec = \case
  CAssign p r t e -> statement p $ do
    -- TC-STMT-7
    tick p
    v <- eval e
    target <- local (\c -> c {cxWriting = True}) (refPath p r)
    storeTarget p t r target v
  CCallFB p c -> statement p (tick p >> callFB p c)
  CEval p e -> statement p (tick p >> () <$ eval e)
  CIf p arms els -> do
    -- TC-STMT-9
    tick p
    let go _ [] = do
          unless (null els) $ note (Branch (posLine p) "no condition is TRUE: ELSE runs")
          execBlock els
        go k ((c, b) : rest) = do
          let arm = if k == (1 :: Int) then "THEN" else "ELSIF branch " <> T.pack (show k)
          v <- noting (\_ v -> Branch (posLine (cePos c)) (if asBool v then "condition TRUE: " <> arm <> " runs" else "condition FALSE")) (eval c)
          if asBool v then execBlock b else go (k + 1) rest
    go 1 arms
  CCase p sel arms els -> do
    -- TC-STMT-11..13: the first group whose labels hold the value
    tick p
    v <- eval sel
    let o = ordinal (ceType sel) v
        which = find (\(_, (ranges, _)) -> any (\(lo, hi) -> o >= lo && o <= hi) ranges) (zip [1 :: Int ..] arms)
    note . Branch (posLine p) $ "selector " <> renderValue v <> ": " <> case which of
      Just (k, _) -> "the labels of branch " <> T.pack (show k) <> " hold it"
      Nothing -> if null els then "no label holds it: nothing runs" else "no label holds it: ELSE runs"
    case which of
      Just (_, (_, b)) -> execBlock b
      Nothing -> execBlock els
  CFor p r t start end step body -> forLoop p r t start end step body
  CWhile p c body -> do
    -- TC-STMT-32
    let l = posLine p
        loop k = do
          tick p
          v <- eval c
          if asBool v
            then do
              continue <- iteration l k (loopBody body)
              if continue then loop (k + 1) else note (LoopExit l k)
            else note (LoopExit l (k - 1))
    note (Rule l (decision ["TC-STMT-32", "NX-STMT-27"] "the condition is tested before each iteration"))
    note (LoopEnter l "WHILE")
    loopEntry p
    loop 1
  CRepeat p body c -> do
    -- TC-STMT-33: at least once, until the condition holds
    testPos <- repeatTestPos p c
    let l = posLine p
        loop k = do
          continue <- iteration l k (loopBody body)
          if continue
            then do
              tick testPos
              v <- eval c
              if asBool v then note (LoopExit l k) else loop (k + 1)
            else note (LoopExit l k)
    note (Rule l (decision ["TC-STMT-33", "NX-STMT-31"] "the body runs first, the condition is tested after each iteration"))
    note (LoopEnter l "REPEAT")
    loopEntry testPos
    loop 1
  CExit p -> tick p >> note (Statement (posLine p)) >> throwError SigExit
  CReturn p -> tick p >> note (Statement (posLine p)) >> throwError SigReturn
  CContinue p -> tick p >> note (Statement (posLine p)) >> throwError SigContinue -- NX-STMT-35
  CJump p l -> tick p >> note (Statement (posLine p)) >> throwError (SigJump l) -- NX-STMT-42
  CLabel _ _ -> pure ()
  CChain p e targets -> do
    -- NX-STMT-6..9: from the rightmost target to the leftmost
    tick p
    pol <- asks cxPol
    v0 <- eval e
    let go _ [] = pure ()
        go v ((op, r, t, from) : rest) = do
          target <- refPath p r
          case op of
            OpAssign -> do
              v' <- maybe (pure v) (\f -> orFault p (convert pol f t v)) from
              storeTarget p t r target v'
              stored <- getRef p r target
              go stored rest
            OpSet -> do
              when (asBool v) (storeTarget p t r target (VBool True))
              go v rest
            OpReset -> do
              when (asBool v) (storeTarget p t r target (VBool False))
              go v rest
    go v0 (reverse targets)
    note (Statement (posLine p))

-- | A loop body; False when EXIT left the loop (TC-STMT-36, TC-STMT-37).
loopBody :: [CStmt] -> Eval Bool
loopBody body = (True <$ execBlock body) `catchError` \case
  SigExit -> pure False
  SigContinue -> pure True
  e -> throwError e

ordinal :: Type -> Value -> Integer
ordinal t v = case (v, t) of
  (VInt _ n, _) -> n
  (VEnum _ n, TEnum _ vs) -> maybe (-1) fst (find ((== key n) . key . snd) (zip [0 ..] vs))
  _ -> -1

-- | FOR (TC-STMT-18..31): the control variable starts at the initial value;
-- before each iteration it is compared with the final value, upwards for a
-- non-negative step, downwards for a negative one (TC-STMT-21, TC-STMT-23);
-- after the body the step is added. Policy @for-bounds@: the final value and
-- the step are evaluated once, before the loop, or each where it is used
-- (the end and the step at every test, the step again at every increment,
-- as C's @for@ does). Where the addition leaves the type, @for-at-type-max@
-- decides: stop, or follow the overflow policy (a wrap can make the loop
-- endless: the watchdog).
forLoop :: Pos -> CRef -> Type -> CExpr -> CExpr -> Maybe CExpr -> [CStmt] -> Eval ()
forLoop p r t start end step body = do
  pol <- asks cxPol
  let stepOf = maybe (pure (forDefaultStep t)) eval step
      l = posLine p
  loopEntry p
  s0 <- eval start
  target <- refPath p r
  storeTarget p t r target s0
  e0 <- eval end
  st0 <- stepOf
  -- TC-STMT-26, TC-STMT-27 (open): policy for-bounds
  note . Rule l . ruled ["TC-STMT-26", "TC-STMT-27", "NX-STMT-25"] "for-bounds" $ case pForBounds pol of
    ForOnce -> "the final value and the step are evaluated once, before the first test"
    ForEveryIteration -> "the final value and the step are evaluated again at every test"
  noteWith (\c -> LoopEnter l (refName c r target <> " from " <> renderValue s0 <> " to " <> renderValue e0 <> " by " <> renderValue st0))
  let current once expr = case pForBounds pol of
        ForOnce -> pure once
        ForEveryIteration -> expr
      loop k = do
        tick p
        e <- current e0 (eval end)
        st <- current st0 stepOf
        i <- getRef p r target
        if not (forGoesOn (intOf i) (intOf e) (intOf st))
          then note (LoopExit l (k - 1))
          else do
            continue <- iteration l k (loopBody body)
            if not continue
              then note (LoopExit l k)
              else do
                i' <- getRef p r target
                stNow <- current st0 stepOf
                let (elemT, fits, ends) = forIncrement pol t i' (intOf stNow)
                -- TC-STMT-31 (open): policy for-at-type-max
                unless fits . note . Rule l . ruled ["TC-STMT-31", "NX-STMT-21"] "for-at-type-max" $
                  renderValue i' <> " + " <> T.pack (show (intOf stNow)) <> " leaves the type of the control variable: "
                    <> (if ends then "the loop ends" else "the increment follows the overflow policy")
                if ends
                  then note (LoopExit l k)
                  else do
                    let stepV = VInt elemT (intOf stNow)
                    v <- operate p BAdd i' stepV
                    -- A13: under stop-at-end the increment is not an addition an
                    -- overflow flag follows (MT-OP-7); under follow-overflow-policy it is
                    when (pForAtTypeMax pol == FollowOverflowPolicy) (flagOverflow (binaryOverflows pol BAdd i' stepV))
                    storeTarget p t r target v
                    loop (k + 1)
  loop 1
  where
    intOf = \case
      VInt _ n -> n
      _ -> 0

-- | TC-STMT-22: without BY the step is 1, of the control variable's type.
forDefaultStep :: Type -> Value
forDefaultStep t = VInt (fromMaybe DINT (baseElem t)) 1

-- | TC-STMT-21, TC-STMT-23: does the loop run again with the control
-- variable at n, the final value e and the step st?
forGoesOn :: Integer -> Integer -> Integer -> Bool
forGoesOn n e st = if st >= 0 then n <= e else n >= e

-- | After an iteration: the type the step is added in, whether the control
-- variable plus the step stays in its type (a subrange's bounds are its
-- type's limits, NX-STMT-22), and whether the loop ends there (policy
-- @for-at-type-max@, TC-STMT-31).
forIncrement :: Policies -> Type -> Value -> Integer -> (Elem, Bool, Bool)
forIncrement pol t i st =
  let elemT = fromMaybe DINT (valueElem i)
      next = (case i of VInt _ n -> n; _ -> 0) + st
      fits = case t of
        TSubrange _ lo hi -> next >= lo && next <= hi
        _ -> fitInt elemT next
   in (elemT, fits, not fits && pForAtTypeMax pol == StopAtEnd)

------------------------------------------------------------------------------
-- Expressions

eval :: CExpr -> Eval Value
eval ce = case ceNode ce of
  CConst v -> pure v
  CRead r -> do
    path <- refPath (cePos ce) r
    noting (\c v -> Read (posLine (cePos ce)) (refName c r path) (renderValue v)) (getRef (cePos ce) r path)
  CUnary o a -> do
    pol <- asks cxPol
    v <- eval a
    r <- orFault (cePos ce) (unary pol o v)
    r <$ flagOverflow (unaryOverflows pol o v)
  CBinary o a b -> do
    pol <- asks cxPol
    x <- eval a
    -- TC-OP-6: short-circuit is a policy; TC-OP-5: the left operand first
    let skipped = x <$ note (Rule (posLine (cePos ce)) (ruled ["TC-OP-6", "NX-OP-22"] "short-circuit" (binOpSymbol o <> " with " <> renderValue x <> " on the left: the right operand is not evaluated")))
    case (o, x, pShortCircuit pol) of
      (BAnd, VBool False, ShortCircuit) -> skipped
      (BOr, VBool True, ShortCircuit) -> skipped
      _ -> do
        y0 <- eval b
        -- NX-ERR-11..13: CheckDiv*'s result is the divisor
        y <- case (o, baseElem (ceType b) >>= checkDivName) of
          (BDiv, Just name) -> implicitCheck (cePos ce) name [y0] >>= maybe (pure y0) (orFault (cePos ce) . convertValue pol (ceType b))
          _ -> pure y0
        r <- operate (cePos ce) o x y
        r <$ flagOverflow (binaryOverflows pol o x y)
  -- NX-CONV-35: TRUNC in a context of another integer type truncates into
  -- that type: beyond it, real-to-int's saturate/wrap half decides
  CConvert (TElem e) (CExpr _ _ (CStandard "TRUNC" [x])) | isInt e -> do
    pol <- asks cxPol
    v <- eval x
    r <- orFault (cePos ce) (truncTo pol e v)
    converted (cePos ce) v r
  CConvert t a -> do
    pol <- asks cxPol
    v <- eval a
    r <- orFault (cePos ce) (convert pol (ceType a) t v)
    converted (cePos ce) v r
  -- NX-OP-87, NX-TASK-9: TIME() (only under standard-library = codesys,
  -- which the checker decides) is the time since the controller started:
  -- the clock the standard FBs read, in TIME's 32 bits
  CStandard f [] | f == timeFunction -> do
    pol <- asks cxPol
    VTime TIME . wrapUnder pol TIME <$> gets mClock
  CStandard "MUX" (k : ins) -> do
    pol <- asks cxPol
    kv <- eval k
    -- NX-OP-67: CODESYS evaluates only the input K selects (under
    -- index-out-of-range = clamp, the input the clamped K selects)
    let chosen i = case pIndexOutOfRange pol of
          IndexClamp -> max 0 (min (toInteger (length ins) - 1) i)
          _ -> i
    vs <- case (pExtensions pol, kv) of
      (ExtensionsCodesys, VInt _ i) -> forM (zip [0 ..] ins) $ \(j, a) -> if j == chosen i then eval a else pure (defaultValue (ceType a))
      _ -> mapM eval ins
    orFault (cePos ce) (standard pol "MUX" (map ceType (k : ins)) (kv : vs))
  CStandard "SEL" [g, a, b] -> do
    pol <- asks cxPol
    gv <- eval g
    -- NX-OP-62 (open; docs/nexto.md): CODESYS evaluates only the input G selects
    vs <- case (pExtensions pol, gv) of
      (ExtensionsCodesys, VBool sel) -> if sel then (\y -> [defaultValue (ceType a), y]) <$> eval b else (\x -> [x, defaultValue (ceType b)]) <$> eval a
      _ -> mapM eval [a, b]
    orFault (cePos ce) (standard pol "SEL" (map ceType [g, a, b]) (gv : vs))
  CStandard f args -> do
    pol <- asks cxPol
    vs <- mapM eval args
    r <- orFault (cePos ce) (standard pol f (map ceType args) vs)
    case (f, vs) of
      ("EXPT", [x, y]) -> flagOverflow (binaryOverflows pol BPow x y)
      _ -> pure ()
    -- a conversion function is told as CConvert is; whether f is one is
    -- asked only when tracing (the name is parsed each time)
    on <- tracing
    case vs of
      [v] | on && isConversionName pol f -> converted (cePos ce) v r
      _ -> pure r
  CCall f ins inouts outs -> callFunction (cePos ce) f ins inouts outs
  CMethod d r ins inouts outs -> callMethod (cePos ce) d r ins inouts outs
  -- a located variable's address: its area's base and its byte
  CAddressOf (CLocated l t) ->
    let (area, a, _, _) = placeOf l t
     in maybe (fault (cePos ce) (Fault "null-pointer" "this direct address has no address a pointer can hold")) (pure . VInt DWORD . (+ a)) (areaBase area)
  CAddressOf r -> do
    path <- refPath (cePos ce) r
    a <- addressOf path
    maybe (fault (cePos ce) (Fault "null-pointer" "this variable has no address")) (pure . VInt DWORD) a

-- | Nesting of calls beyond which a cycle ends with @call-depth@ (the
-- preset's @pCallDepth@: MasterTool's 16, MT-POU-9, MT-ERR-2050).
callDepthLimit :: Pos -> Int -> Eval ()
callDepthLimit p depth = do
  pol <- asks cxPol
  when (depth >= pCallDepth pol) (fault p (Fault "call-depth" "calls nest too deeply"))

-- | MT-OP-7 (policy @overflow-flag@): an operation an overflow flag follows
-- sets the controller's flag, the global 'overflowFlagName', to whether it
-- overflowed; 'Nothing' (another operation) leaves it. Without the policy,
-- or where the controller declares no such global, nothing is written.
flagOverflow :: Maybe Bool -> Eval ()
flagOverflow Nothing = pure ()
flagOverflow (Just o) = do
  pol <- asks cxPol
  when (pOverflowFlag pol == InternalOverflowFlag) $
    modify' (\m -> m {mGlobals = M.adjust (const (VBool o)) overflowFlagName (mGlobals m)})

-- | A binary operator's value; where a policy decided it, the rule goes to
-- the trace.
operate :: Pos -> BinOp -> Value -> Value -> Eval Value
operate p o x y = do
  pol <- asks cxPol
  on <- tracing
  if on
    then do
      let (r, why) = binaryWhy pol o x y
      mapM_ (note . Rule (posLine p)) why
      orFault p r
    else orFault p (binary pol o x y)

-- | A conversion's result; when tracing, a result that is not its
-- argument's number is shown with the policy that made it so:
-- @real-to-int@ from REAL or LREAL to an integer (rounded, clamped or
-- wrapped), @narrow-int@ between integers, @real-overflow@ for LREAL to
-- REAL's infinity.
converted :: Pos -> Value -> Value -> Eval Value
converted p from to = do
  on <- tracing
  when on $ case (realOf from, to) of
    (Just r, VInt e n)
      | isNaN r || isInfinite r || toRational r /= toRational n ->
          rule ["TC-CONV-12", "NX-CONV-23", "NX-CONV-24", "NX-ERR-22"] "real-to-int" (renderValue from <> " to " <> elemName e <> " gives " <> T.pack (show n))
    (Just r, VReal f)
      | isInfinite f && not (isInfinite r) ->
          rule ["TC-OP-26"] "real-overflow" (renderValue from <> " does not fit REAL: " <> renderValue to)
    _ -> case (from, to) of
      (VInt _ a, VInt e b)
        | a /= b -> rule ["TC-CONV-13", "TC-CONV-14", "NX-ERR-23"] "narrow-int" (T.pack (show a) <> " does not fit " <> elemName e <> ": it becomes " <> T.pack (show b))
      _ -> pure ()
  pure to
  where
    rule ids policy says = note (Rule (posLine p) (ruled ids policy says))
    realOf = \case
      VReal x -> Just (float2Double x)
      VLReal x -> Just x
      _ -> Nothing

-- | A method, accessor or action called on an instance (NX-POU-25..43):
-- which one runs is the instance's own type's (or the nearest base's) for a
-- virtual call (NX-POU-31, NX-POU-34), the named type's for SUPER^
-- (NX-POU-46). A method runs in a fresh frame with the instance as THIS
-- (NX-POU-26, NX-POU-27); an action runs on the instance's variables, its
-- inputs written first (NX-POU-43). @=>@ outputs are copied after.
callMethod :: Pos -> Dispatch -> CRef -> [(Text, CExpr)] -> [(Text, CRef)] -> [(Text, CRef, Type)] -> Eval Value
callMethod p d r ins inouts outs = do
  prog <- asks cxProgram
  inst <- refPath p r
  self <- getPath inst
  let (owner, m) = case (d, self) of
        (Virtual k, VInstance t _) -> (key t, k)
        (Virtual k, _) -> ("", k)
        (Static t k, _) -> (t, k)
  md <- maybe (fault p (Fault "call-depth" ("no method " <> m <> " for " <> owner))) pure (findMethod prog owner m)
  inputs <- forM ins $ \(k, e) -> (k,) <$> eval e
  refs <- forM inouts $ \(k, x) -> (k,x,) <$> refPath p x
  depth <- asks cxDepth
  callDepthLimit p depth
  case pdKind md of
    KAction -> do
      td <- maybe (fault p (Fault "call-depth" ("unknown type " <> owner))) pure (lookupPou prog owner)
      forM_ inputs $ \(k, v) -> storePath p (paramType td k) (extend inst (StepField k)) v
      bindInOuts inst refs
      local (\cx -> cx {cxSelf = inst, cxThis = inst, cxDepth = depth + 1}) (callBody md)
      copyBack inst refs
      copyOutputs p inst outs
      pure (VBool False)
    _ -> callFunctionWith p md (Just inst) inputs refs outs

-- | NX-ERR-1, NX-ERR-2: the check function of a division by its divisor's type.
checkDivName :: Elem -> Maybe Text
checkDivName e
  | e == REAL = Just "CHECKDIVREAL"
  | e == LREAL = Just "CHECKDIVLREAL"
  | isInt e && intBits e <= 16 = Just "CHECKDIVINT"
  | isInt e && intBits e == 32 = Just "CHECKDIVDINT"
  | isInt e = Just "CHECKDIVLINT"
  | otherwise = Nothing

intValue :: Value -> Integer
intValue = \case
  VInt _ n -> n
  VBool b -> if b then 1 else 0
  _ -> 0

-- | The largest unstructured type inside a type, in bytes (CheckPointer's
-- iGran, NX-ERR-19).
granularity :: Layout -> Type -> Integer
granularity ly t = case t of
  TArray _ et -> granularity ly et
  TStruct _ fs -> maximum (1 : [granularity ly ft | (_, ft) <- fs])
  TUnion _ fs -> maximum (1 : [granularity ly ft | (_, ft) <- fs])
  TFB n -> maximum (1 : [granularity ly ft | (_, ft) <- lyMembers ly n])
  _ -> sizeInBytes ly t

------------------------------------------------------------------------------
-- Variables

-- | Where a reference lies now: indices evaluated and checked (policy
-- @index-out-of-range@), VAR_IN_OUT parameters followed to the caller's
-- variable.
refPath :: Pos -> CRef -> Eval RefPath
refPath p = \case
  CLocal k -> do
    self <- asks cxSelf
    follow (extend self (StepField k))
  CGlobal k -> pure (RefPath (RootGlobal k) [])
  CField r f -> do
    base <- refPath p r
    follow (extend base (StepField f))
  CIndex r ixs -> do
    base <- refPath p r
    arr <- getPath base
    is <- mapM eval ixs
    let ns = [n | VInt _ n <- is]
    case arr of
      VArray bs _ -> do
        pol <- asks cxPol
        checked <- forM (zip ns bs) $ \(n0, (lo, hi)) -> do
          -- NX-ERR-5..8: CheckBounds' result is the index
          n <- maybe n0 intValue <$> implicitCheck p "CHECKBOUNDS" [VInt DINT n0, VInt DINT lo, VInt DINT hi]
          let (r, why) = indexWhy pol (lo, hi) n
          mapM_ (note . Rule (posLine p)) why
          orFault p r
        pure (extend base (StepIndex checked))
      _ -> pure (extend base (StepIndex ns))
  -- MT-MAP-9: an array at a direct address is the bytes of the row it covers
  CLocated l t@(TArray {}) -> let (area, a, _, _) = placeOf l t in pure (RefPath (RootBytes area a t) [])
  CLocated l _ -> pure (RefPath (RootLocated (locText l)) [])
  CDeref e t -> do
    -- NX-TYPE-75: the variable of the pointer's base type at its address;
    -- NX-ERR-19: CheckPointer sees the access first, its result is used
    v0 <- eval e
    writing <- asks cxWriting
    ly <- asks (mmLayout . cxMemory)
    v <- maybe v0 (VInt DWORD . intValue) <$> implicitCheck p "CHECKPOINTER" [v0, VInt DINT (sizeInBytes ly t), VInt DINT (granularity ly t), VBool writing]
    case v of
      VInt _ 0 -> fault p (Fault "null-pointer" "the pointer is 0: it points at no variable")
      VInt _ a -> do
        found <- variableAt a t
        case found of
          Just path -> pure path
          Nothing -> do
            -- NX-TYPE-75: the value stored at the address, read as the
            -- pointer's type from the variables whose bytes lie there
            -- (an array of other bounds element by element); a type with
            -- an FB in it needs an instance there (docs/nexto.md)
            mm <- asks cxMemory
            inside <- gets (\m -> covered mm m a (sizeInBytes ly t))
            if plainData t && inside
              then pure (RefPath (RootAt a t) [])
              else fault p (Fault "null-pointer" ("no variable of type " <> typeText t <> " lies at the address 16#" <> T.pack (showHex a "")))
      _ -> fault p (Fault "null-pointer" "not an address")
  CCharAt w r i -> do
    base <- refPath p r
    iv <- eval i
    case iv of
      VInt _ n -> pure (extend base (StepChar w n))
      _ -> pure base
  CProgram k -> pure (RefPath (RootProgram k) [])
  CBit r i -> (`extend` StepBit i) <$> refPath p r
  CThis -> asks cxThis
  CInstance k -> do
    this <- asks cxThis
    follow (extend this (StepField k))
  where
    follow path = do
      v <- getPathOr path (VBool False)
      case v of
        VRef r -> pure r
        _ -> pure path

-- | An index checked against its dimension's bounds (policy
-- @index-out-of-range@, TC-ERR-3): the index used, and the rule when it
-- was clamped.
indexWhy :: Policies -> (Integer, Integer) -> Integer -> (Either Fault Integer, [Decision])
indexWhy pol (lo, hi) n
  | n >= lo && n <= hi = (Right n, [])
  | otherwise = case pIndexOutOfRange pol of
      IndexClamp -> (Right (max lo (min hi n)), [ruled ["TC-ERR-3", "NX-ERR-9"] "index-out-of-range" ("the index " <> T.pack (show n) <> " lies outside " <> T.pack (show lo) <> ".." <> T.pack (show hi) <> ": clamped to " <> T.pack (show (max lo (min hi n))))])
      _ -> (Left (Fault "index-out-of-range" ("the index " <> T.pack (show n) <> " lies outside the bounds " <> T.pack (show lo) <> ".." <> T.pack (show hi))), [])

-- | Read a reference (located variables from the bytes).
getRef :: Pos -> CRef -> RefPath -> Eval Value
getRef _ r path = case r of
  CLocated l t -> located l t
  _ -> getPath path

-- | A located variable's value, read from its bytes.
located :: Location -> Type -> Eval Value
located l t = do
  range <- asks (prTimeRange . cxProgram)
  gets (readLocated range l t . mMemory)

-- | Store into a target of a declared type: strings cut to their capacity
-- (policy @string-overflow@), subranges checked (policy @subrange@).
storeTarget :: Pos -> Type -> CRef -> RefPath -> Value -> Eval ()
storeTarget p t r path v = do
  v' <- fitValue p t v
  noting (\c _ -> Wrote (posLine p) (refName c r path) (renderValue v')) $ case r of
    CLocated l _ -> modify' (\m -> m {mMemory = writeLocated l t v' (mMemory m)})
    _ -> putPath path v'

storePath :: Pos -> Type -> RefPath -> Value -> Eval ()
storePath p t path v = fitValue p t v >>= putPath path

fitValue :: Pos -> Type -> Value -> Eval Value
fitValue p t v0 = do
  pol <- asks cxPol
  v <- case (t, v0) of
    (TSubrange e lo hi, VInt e' n0) -> do
      -- NX-ERR-15, NX-ERR-16: CheckRangeSigned/Unsigned's result is stored
      let name = if isSignedInt e then "CHECKRANGESIGNED" else "CHECKRANGEUNSIGNED"
      VInt e' . maybe n0 intValue <$> implicitCheck p name [VInt DINT n0, VInt DINT lo, VInt DINT hi]
    _ -> pure v0
  let (r, why) = fitWhy pol t v
  mapM_ (note . Rule (posLine p)) why
  orFault p r

-- | The value a target of a declared type stores, and the rules a policy
-- decided on the way: strings cut to their capacity (policy
-- @string-overflow@), integers computed wider than their type narrowed
-- (@narrow-int@), subranges checked (@subrange@).
fitWhy :: Policies -> Type -> Value -> (Either Fault Value, [Decision])
fitWhy pol t v = case (t, v) of
  (TString _ cap, VString s)
    | T.length s > cap -> case pStringOverflow pol of
        StringTruncate ->
          -- TC-TYPE-27
          ( Right (VString (T.take cap s))
          , [ruled ["TC-TYPE-27", "NX-TYPE-27"] "string-overflow" ("a string of " <> T.pack (show (T.length s)) <> " characters is cut to the capacity " <> T.pack (show cap))]
          )
        StringOverflowError -> (Left (Fault "index-out-of-range" ("a string of " <> T.pack (show (T.length s)) <> " characters does not fit a STRING[" <> T.pack (show cap) <> "]")), [])
  -- a value computed wider than its type (arith-width = promote-32) is
  -- narrowed on the store, by the policy narrow-int
  (TElem e, VInt _ n)
    | isInt e && not (fitInt e n) ->
        let n' = case pNarrowInt pol of
              NarrowWrap -> wrapInt e n
              NarrowSaturate -> let (lo, hi) = intRange e in max lo (min hi n)
         in (Right (VInt e n'), [ruled ["TC-CONV-13", "NX-ERR-23"] "narrow-int" (T.pack (show n) <> " does not fit " <> elemName e <> ": stored as " <> T.pack (show n'))])
  (TSubrange e lo hi, VInt _ n)
    | (n < lo || n > hi) && pSubrange pol == SubrangeError ->
        (Left (Fault "subrange" ("the value " <> T.pack (show n) <> " lies outside the subrange " <> T.pack (show lo) <> ".." <> T.pack (show hi) <> " " <> citing pol (faultRules "subrange"))), [])
    | otherwise ->
        ( Right (VInt e (wrapInt e n))
        , [ruled ["TC-TYPE-33", "NX-ERR-17"] "subrange" (T.pack (show n) <> " lies outside " <> T.pack (show lo) <> ".." <> T.pack (show hi) <> ": stored unchecked") | (n < lo || n > hi) && pSubrange pol == SubrangeUnchecked]
        )
  -- TC-TYPE-33: an array or structure copied whole stores each element or
  -- field of a subrange type as that subrange's store would
  (TArray _ et, VArray bs xs) | holdsSubrange et ->
    let rs = fmap (fitWhy pol et) xs
     in (VArray bs <$> traverse fst rs, concatMap snd (toList rs))
  (TStruct _ fs, VStruct m) | any (holdsSubrange . snd) fs ->
    let rs = [(k, fitWhy pol ft x) | (n, ft) <- fs, let k = upperName n, Just x <- [M.lookup k m], holdsSubrange ft]
     in (VStruct . foldr (uncurry M.insert) m <$> traverse (traverse fst) rs, concatMap (snd . snd) rs)
  _ -> (Right v, [])
  where
    holdsSubrange = \case
      TSubrange {} -> True
      TArray _ et -> holdsSubrange et
      TStruct _ fs -> any (holdsSubrange . snd) fs
      _ -> False

rootValue :: MemoryMap -> Root -> Machine -> Maybe Value
rootValue mm r m = case r of
  RootGlobal k -> M.lookup k (mGlobals m)
  RootProgram k -> M.lookup k (mPrograms m)
  RootFrame d -> M.lookup d (mFrames m)
  RootLocated _ -> Nothing
  RootBytes area a t -> Just (decode ly t [fromInteger (M.findWithDefault 0 (area, a + i) (mMemory m)) | i <- [0 .. sizeInBytes ly t - 1]])
  RootAt a t -> Just (decode ly t (bytesAt mm m a (sizeInBytes ly t)))
  where
    ly = mmLayout mm

setRoot :: MemoryMap -> Root -> Value -> Machine -> Machine
setRoot mm r v m = case r of
  RootGlobal k -> m {mGlobals = M.insert k v (mGlobals m)}
  RootProgram k -> m {mPrograms = M.insert k v (mPrograms m)}
  RootFrame d -> m {mFrames = M.insert d v (mFrames m)}
  RootLocated _ -> m
  RootBytes area a t -> m {mMemory = foldl (\mem (i, byte) -> M.insert (area, a + i) (toInteger byte) mem) (mMemory m) (zip [0 ..] (encode ly t v))}
  RootAt a t -> putBytesAt mm a (encode ly t v) m
  where
    ly = mmLayout mm

-- | The bytes from an address (NX-TYPE-75): each taken from the variable
-- that holds it, a scalar, string or union, as its value's bytes
-- ('encode'); a direct-address area's from its bytes; a padding byte, or
-- one where no variable lies, 0.
bytesAt :: MemoryMap -> Machine -> Integer -> Integer -> [Word8]
bytesAt mm m a n = go a
  where
    ly = mmLayout mm
    end = a + n
    go x
      | x >= end = []
      | Just (area, byte) <- areaAt x = fromInteger (M.findWithDefault 0 (area, byte) (mMemory m) .&. 255) : go (x + 1)
      | Just (r, steps, lt, from) <- leafOf mm m x =
          let k = min (sizeInBytes ly lt - from) (end - x)
              bs = case rootValue mm r m >>= walk ly steps of
                Just v | notRef v -> encode ly lt v
                _ -> []
           in take (fromInteger k) (drop (fromInteger from) bs ++ repeat 0) ++ go (x + k)
      | otherwise = 0 : go (x + 1)

-- | Bytes written from an address: each variable that holds some of them
-- gets its value's bytes with those replaced ('decode'); a padding byte, or
-- one where no variable lies, is dropped.
putBytesAt :: MemoryMap -> Integer -> [Word8] -> Machine -> Machine
putBytesAt mm x bytes m = case bytes of
  [] -> m
  b : rest
    | Just (area, byte) <- areaAt x -> putBytesAt mm (x + 1) rest (m {mMemory = M.insert (area, byte) (toInteger b) (mMemory m)})
    | Just (r, steps, lt, from) <- leafOf mm m x ->
        let k = fromInteger (min (sizeInBytes ly lt - from) (toInteger (length bytes)))
            (mine, others) = splitAt k bytes
            m' = fromMaybe m $ do
              root <- rootValue mm r m
              old <- walk ly steps root
              guard (notRef old)
              let bs = encode ly lt old
                  at = fromInteger from
              pure (setRoot mm r (updateAt ly steps (decode ly lt (take at bs ++ mine ++ drop (at + k) bs)) root) m)
         in putBytesAt mm (x + toInteger k) others m'
    | otherwise -> putBytesAt mm (x + 1) rest m
  where
    ly = mmLayout mm

-- | The root, path and type of the innermost variable holding the byte at
-- an address, and the byte's offset inside it.
leafOf :: MemoryMap -> Machine -> Integer -> Maybe (Root, [Step], Type, Integer)
leafOf mm m x = do
  (r, rt, base) <- find (\(_, rt, base) -> x >= base && x < base + sizeInBytes (mmLayout mm) rt) (rootsIn mm m)
  (steps, lt, at) <- leafAt (mmLayout mm) rt (x - base)
  Just (r, steps, lt, x - base - at)

-- | A VAR_IN_OUT's reference is no data of its own.
notRef :: Value -> Bool
notRef = \case
  VRef _ -> False
  _ -> True

-- | Does every byte from an address on lie in a root of memory (a global,
-- a program instance, a call's frame) or a direct-address area?
covered :: MemoryMap -> Machine -> Integer -> Integer -> Bool
covered mm m a n = go a
  where
    end = a + max 1 n
    go x
      | x >= end = True
      | isJust (areaAt x) = go (x + 1)
      | otherwise = case [base + sizeInBytes (mmLayout mm) rt | (_, rt, base) <- rootsIn mm m, x >= base, x < base + sizeInBytes (mmLayout mm) rt] of
          next : _ -> go next
          [] -> False

getPath :: RefPath -> Eval Value
getPath path = getPathOr path (VBool False)

getPathOr :: RefPath -> Value -> Eval Value
getPathOr path dflt = do
  RefPath r steps <- narrowed path
  mm <- asks cxMemory
  gets (\m -> fromMaybe dflt (rootValue mm r m >>= walk (mmLayout mm) steps))

-- | A path into a direct-address area's bytes reaches the bytes of its
-- leaf: its fields and indices are offsets in the pointer's type, in the
-- program's layout (pack_mode included, as ADR sees it); only the leaf's
-- bytes are read or written, never the bytes around it.
narrowed :: RefPath -> Eval RefPath
narrowed path = case path of
  RefPath (RootBytes area a t) steps@(_ : _) -> do
    ly <- asks (mmLayout . cxMemory)
    let go off ty = \case
          s : rest
            | offsetStep s, Just (o, ft) <- offsetOf ly ty [s] -> go (off + o) ft rest
          rest -> RefPath (RootBytes area off ty) rest
        offsetStep = \case
          StepField _ -> True
          StepIndex _ -> True
          _ -> False
    pure (go a t steps)
  -- a view's fields and indices are offsets in its type; where a variable
  -- of the type found there starts, the path is that variable's
  RefPath (RootAt a t) steps@(_ : _) -> do
    ly <- asks (mmLayout . cxMemory)
    let go off ty = \case
          s : rest
            | offsetStep s, Just (o, ft) <- offsetOf ly ty [s] -> go (off + o) ft rest
          rest -> (off, ty, rest)
        offsetStep = \case
          StepField _ -> True
          StepIndex _ -> True
          _ -> False
        (at, ty, rest) = go a t steps
    exact <- variableAt at ty
    pure $ case exact of
      Just (RefPath r s) -> RefPath r (s ++ rest)
      Nothing -> RefPath (RootAt at ty) rest
  _ -> pure path

-- | The part of a value at a path; a union's member is read from its bytes
-- in the program's layout.
walk :: Layout -> [Step] -> Value -> Maybe Value
walk _ [] v = Just v
walk ly (s : rest) v = case (s, v) of
  (StepField f, VStruct fs) -> M.lookup f fs >>= walk ly rest
  (StepField f, VUnion {}) -> unionMember ly f v >>= walk ly rest
  (StepField f, VInstance _ fs) -> M.lookup f fs >>= walk ly rest
  (StepIndex is, VArray bs xs) -> Seq.lookup (linearIndex bs is) xs >>= walk ly rest
  (StepBit i, VInt e n) -> walk ly rest (VBool (testBit (n `mod` (2 ^ intBits e)) i))
  (StepChar w i, VString str) -> walk ly rest (VInt (if w then WORD else BYTE) (if i >= 0 && i < toInteger (T.length str) then toInteger (ord (T.index str (fromInteger i))) else 0))
  _ -> Nothing

putPath :: RefPath -> Value -> Eval ()
putPath path v = narrowed path >>= \(RefPath r steps) -> asks cxMemory >>= \mm -> modify' $ \m -> case rootValue mm r m of
  Just root -> setRoot mm r (updateAt (mmLayout mm) steps v root) m
  Nothing -> m

-- | A value with the part at a path replaced (a missing field is added).
updateAt :: Layout -> [Step] -> Value -> Value -> Value
updateAt ly steps v = go steps
  where
    go [] _ = v
    go (s : rest) old = case (s, old) of
      (StepField f, VStruct fs) -> VStruct (M.insert f (go rest (M.findWithDefault (VBool False) f fs)) fs)
      (StepField f, VUnion {}) -> setUnionMember ly f (go rest) old
      (StepField f, VInstance n fs) -> VInstance n (M.insert f (go rest (M.findWithDefault (VBool False) f fs)) fs)
      (StepIndex is, VArray bs xs) -> VArray bs (Seq.adjust' (go rest) (linearIndex bs is) xs)
      -- NX-OP-93: a bit set or cleared, the rest of the integer kept
      (StepBit i, VInt e n) | VBool b <- v ->
        let u = n `mod` (2 ^ intBits e)
         in VInt e (wrapInt e (if b then setBit u i else clearBit u i))
      -- NX-TYPE-77: writing a character inside the string; beyond its end
      -- nothing changes
      (StepChar _ i, VString str) | i >= 0 && i < toInteger (T.length str), VInt _ c <- v ->
        let (before, after) = T.splitAt (fromInteger i) str
         in VString (before <> T.singleton (chr (fromInteger c)) <> T.drop 1 after)
      _ -> old

-- | TC-TYPE-43: the rightmost index varies fastest.
linearIndex :: [(Integer, Integer)] -> [Integer] -> Int
linearIndex bs is = fromInteger (foldl (\acc ((lo, hi), i) -> acc * (hi - lo + 1) + (i - lo)) 0 (zip bs is))

------------------------------------------------------------------------------
-- Addresses (CODESYS pointers, Stref.IEC.Memory)

layoutOf :: Program -> Layout
layoutOf prog = remembering types (layout (\n -> M.findWithDefault [] (key n) members) (`M.lookup` prPackModes prog) (prTimeRange prog))
  where
    members = M.map (\d -> [(viKey v, viType v) | v <- pdVars d, viAt v == Nothing]) (prPous prog)
    -- the types of the variables, and of the instances of each POU
    types = map viType (prGlobals prog) ++ concat [TFB (pdName d) : TProgram (pdName d) : TProgram k : map viType (pdVars d) | (k, d) <- M.toList (prPous prog)]

-- | The program's layout and the roots of memory that stay where they are
-- during a cycle (globals and program instances) with their types,
-- addresses and sizes: what 'roots' would compute again at every address.
data MemoryMap = MemoryMap
  { mmLayout :: Layout
  , mmRoots :: [(Root, Type, Integer)]
  }

memoryMap :: Program -> MemoryMap
memoryMap prog = MemoryMap ly (globals ++ programs)
  where
    ly = layoutOf prog
    globals = placeAll ly globalsBase [(RootGlobal (viKey v), viType v) | v <- prGlobals prog, viAt v == Nothing]
    programs = placeAll ly programsBase [(RootProgram (key inst), TProgram t) | (inst, t) <- prRoots prog]

-- | The roots of memory with their types and addresses: globals, program
-- instances, the frames of the calls under way.
roots :: Eval [(Root, Type, Integer)]
roots = do
  mm <- asks cxMemory
  gets (rootsIn mm)

rootsIn :: MemoryMap -> Machine -> [(Root, Type, Integer)]
rootsIn mm m = mmRoots mm ++ [(RootFrame d, TProgram n, frameBase d) | (d, VInstance n _) <- M.toList (mFrames m)]

addressOf :: RefPath -> Eval (Maybe Integer)
addressOf (RefPath r steps) = do
  ly <- asks (mmLayout . cxMemory)
  rs <- roots
  pure $ do
    (t, base) <- case r of
      RootBytes area a t -> (t,) . (+ a) <$> areaBase area
      RootAt a t -> Just (t, a)
      _ -> (\(_, t, base) -> (t, base)) <$> find (\(r', _, _) -> r' == r) rs
    (off, _) <- offsetOf ly t steps
    pure (base + off)

-- | The variable of a type at an address: the root whose bytes hold it,
-- then the path inside.
variableAt :: Integer -> Type -> Eval (Maybe RefPath)
variableAt a t = do
  ly <- asks (mmLayout . cxMemory)
  rs <- roots
  pure $ case areaAt a of
    -- in a direct-address area: its bytes, read as the pointer's type
    Just (area, byte) -> Just (RefPath (RootBytes area byte t) [])
    Nothing -> do
      (r, rt, base) <- find (\(_, rt, base) -> a >= base && a < base + max 1 (sizeInBytes ly rt)) rs
      RefPath r <$> locate ly rt (a - base) t

------------------------------------------------------------------------------
-- Located variables (TC-ADDR-*): bytes of the areas I (= X), Q (= Y), M (=
-- R) and S, multi-byte values little-endian (docs/tecomat.md)

areaOf :: Char -> Char
areaOf = \case
  'X' -> 'I'
  'Y' -> 'Q'
  'R' -> 'M'
  c -> c

-- | The first byte, the bit (for a bit) and the width in bytes.
placeOf :: Location -> Type -> (Char, Integer, Maybe Int, Int)
placeOf l t = case (t, locAddress l) of
  (TElem BOOL, [b, bit]) -> (area, b, Just (fromInteger bit), 1)
  -- NX-TYPE-18: a BOOL at a byte or word address is the whole first byte
  (TElem BOOL, [a]) | byteSized l -> (area, a, Nothing, 1)
  (TElem BOOL, [n]) -> (area, n `div` 8, Just (fromInteger (n `mod` 8)), 1)
  (_, a : _) -> (area, a, Nothing, width)
  _ -> (area, 0, Nothing, width)
  where
    area = areaOf (locArea l)
    width = case baseElem t of
      Just e | isInt e -> intBits e `div` 8
      Just REAL -> 4
      Just LREAL -> 8
      Just TIME -> 4
      _ -> 1

-- | The elements of an array at a direct address (MT-MAP-9): one after the
-- other from its first byte, each as wide as its type, as the layout lays
-- out an array of elementary values.
elementLocations :: Location -> [(Integer, Integer)] -> Type -> [Location]
elementLocations l b et =
  let (_, a, _, width) = placeOf l et
   in [l {locAddress = [a + i * toInteger width]} | i <- [0 .. product [hi - lo + 1 | (lo, hi) <- b] - 1]]

-- | A TIME is read as the policy time-range counts it: a signed count, or a
-- DWORD's (NX-TYPE-30).
readLocated :: TimeRange -> Location -> Type -> M.Map (Char, Integer) Integer -> Value
readLocated range l (TArray b et) mem = VArray b (Seq.fromList [readLocated range l' et mem | l' <- elementLocations l b et])
readLocated range l t mem =
  let (area, a, bit, width) = placeOf l t
      byte i = M.findWithDefault 0 (area, a + toInteger i) mem
      raw = sum [byte i `shiftL` (8 * i) | i <- [0 .. width - 1]]
   in case (baseElem t, bit) of
        (Just BOOL, Just b) -> VBool (testBit (byte (0 :: Int)) b)
        (Just REAL, _) -> VReal (castWord32ToFloat (fromInteger raw))
        (Just LREAL, _) -> VLReal (castWord64ToDouble (fromInteger raw))
        (Just TIME, _) -> VTime TIME (if range == TimeUnsigned then raw else wrapInt TIME raw)
        (Just BOOL, Nothing) -> VBool (raw /= 0)
        (Just e, _) -> VInt e (wrapInt e raw)
        _ -> defaultValue t

writeLocated :: Location -> Type -> Value -> M.Map (Char, Integer) Integer -> M.Map (Char, Integer) Integer
writeLocated l (TArray b et) (VArray _ xs) mem = foldl (\m (l', x) -> writeLocated l' et x m) mem (zip (elementLocations l b et) (toList xs))
writeLocated l t v mem =
  let (area, a, bit, width) = placeOf l t
      raw = case v of
        VInt _ n -> n
        VBool b -> if b then 1 else 0
        VReal f -> toInteger (castFloatToWord32 f)
        VLReal d -> toInteger (castDoubleToWord64 d)
        VTime _ n -> n
        _ -> 0
      unsignedRaw = raw `mod` (2 ^ (8 * width))
   in case bit of
        Just b ->
          let old = M.findWithDefault 0 (area, a) mem
           in M.insert (area, a) (if raw /= 0 then setBit old b else clearBit old b) mem
        Nothing -> foldl (\m i -> M.insert (area, a + toInteger i) ((unsignedRaw `shiftR` (8 * i)) .&. 255) m) mem [0 .. width - 1]

------------------------------------------------------------------------------
-- Observation

-- | The value at a variable path of corpus-format §4.1: @G@, @MAIN.x@,
-- @MAIN.fb.Q@, @MAIN.a[2,3]@, @MAIN.r.f@; located variables read from their
-- bytes. Nothing when the path names nothing.
readVariablePath :: Program -> Machine -> [Step] -> Maybe (Value, Maybe Type)
readVariablePath prog m = readPath . throughList prog
  where
    readPath = \case
      StepField first : rest
        | Just inst <- M.lookup first (mPrograms m) -> do
            (_, t) <- find ((== first) . key . fst) (prRoots prog)
            d <- lookupPou prog t
            fromInstance d inst rest
        | otherwise -> case find ((== first) . viKey) (prGlobals prog) of
            Just v | Just l <- viAt v, null rest -> Just (readLocated (prTimeRange prog) l (viType v) (mMemory m), Just (viType v))
            Just v -> (,Nothing) <$> (M.lookup first (mGlobals m) >>= walkFollow rest) >>= \(x, _) -> Just (x, typeAt (viType v) rest)
            Nothing -> Nothing
      _ -> Nothing
    fromInstance d inst rest = case rest of
      StepField k : more | Just v <- varByKey d k, Just l <- viAt v, null more -> Just (readLocated (prTimeRange prog) l (viType v) (mMemory m), Just (viType v))
      StepField k : more | Just v <- varByKey d k -> do
        x <- walkFollow rest inst
        pure (x, typeAt (viType v) more)
      _ -> (,Nothing) <$> walkFollow rest inst
    walkFollow steps v = case walk ly steps v of
      Just (VRef (RefPath r s)) -> rootValue (memoryMap prog) r m >>= walk ly s
      x -> x
    ly = layoutOf prog
    typeAt t = \case
      [] -> Just t
      StepField f : more -> case t of
        TStruct _ fs -> lookup f [(key n, ft) | (n, ft) <- fs] >>= \ft -> typeAt ft more
        TUnion _ fs -> lookup f [(key n, ft) | (n, ft) <- fs] >>= \ft -> typeAt ft more
        TFB n -> lookupPou prog n >>= \d -> varByKey d f >>= \v -> typeAt (viType v) more
        _ -> Nothing
      StepIndex _ : more -> case t of
        TArray _ et -> typeAt et more
        _ -> Nothing
      StepChar w _ : more -> typeAt (TElem (if w then WORD else BYTE)) more
      StepBit _ : more -> typeAt (TElem BOOL) more

-- | A path that starts with a named global list's name, @GVL.x@, to the
-- variable as it is stored (NX-VAR-35).
throughList :: Program -> [Step] -> [Step]
throughList prog = \case
  StepField l : StepField x : rest | Just k <- M.lookup l (prGvls prog) >>= M.lookup x -> StepField k : rest
  steps -> steps

-- | Write a variable at a path before a cycle (the corpus's @set@, §4.1).
writeVariablePath :: Program -> Machine -> [Step] -> Value -> Maybe Machine
writeVariablePath prog m steps0 v = case throughList prog steps0 of
  StepField first : rest
    | M.member first (mPrograms m) -> located first rest (RefPath (RootProgram first) rest)
    | Just g <- find ((== first) . viKey) (prGlobals prog) -> case viAt g of
        Just l | null rest -> Just (writeLocatedVar l (viType g) v m)
        _ -> put (RefPath (RootGlobal first) rest)
  _ -> Nothing
  where
    located inst rest path = do
      (_, t) <- find ((== inst) . key . fst) (prRoots prog)
      d <- lookupPou prog t
      case rest of
        [StepField k] | Just var <- varByKey d k, Just l <- viAt var -> Just (writeLocatedVar l (viType var) v m)
        _ -> put path
    -- the path exists (walk), so updateAt adds no field
    put (RefPath r s) = do
      root <- rootValue mm r m
      _ <- walk ly s root
      Just (setRoot mm r (updateAt ly s v root) m)
    mm = memoryMap prog
    ly = layoutOf prog

readLocatedVar :: Program -> Location -> Type -> Machine -> Value
readLocatedVar prog l t m = readLocated (prTimeRange prog) l t (mMemory m)

writeLocatedVar :: Location -> Type -> Value -> Machine -> Machine
writeLocatedVar l t v m = m {mMemory = writeLocated l t v (mMemory m)}
