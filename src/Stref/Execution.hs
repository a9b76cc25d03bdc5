{-# OPTIONS_GHC -O2 #-}
-- (the interpreter's hot path: bench/RESULTS.md measures -O2 against -O1)
{-# LANGUAGE RankNTypes #-}

-- | One module call (MT-EXEC-9): the pure function from the checked module,
-- the controller's state and the call's inputs to the new state, the output
-- signals and the diagnostics.
--
-- The life cycle of a call:
--
-- 0. INPUT1 FALSE: the module does not run (MT-SIG-3); nothing changes and
--    OUTPUT1..3 read FALSE.
-- 1. Checks before the first statement, with the line of decision A2: every
--    mapped operand is declared (2000-2002, MT-MAP-8, MT-MAP-10), then the CHF
--    parameters (2003-2012, MT-PARAM-3..7).
-- 2. The data area is initialised (every call, or only the first under
--    @lifetime = retained@), mapped variables with an initialiser are
--    written (decision A3), VAR_OUTPUT start at their default (A21);
--    VAR_INPUT and VAR_IN_OUT are copied in from the CHF inputs.
-- 3. OUTPUT1 := TRUE, OUTPUT2 := OUTPUT3 := FALSE (MT-SIG-4),
--    INTERNAL_OVERFLOW := FALSE (A5).
-- 4. The PROGRAM body runs.
-- 5. Normal end (RETURN included, MT-STMT-5): VAR_IN_OUT are copied back,
--    VAR_OUTPUT written to the CHF outputs, diagnostics [-32768,0,0,0,0]
--    (MT-DIAG-4, A29).
-- 6. Runtime error: the call stops at once (MT-EXEC-8), diagnostics [line,
--    code, c1, c2, c3] (MT-DIAG-2), OUTPUT1 := FALSE (MT-SIG-5), no copy-back
--    (A19); operand writes already made persist.
module Stref.Execution
  ( PlcState (..)
  , initialPlcState
  , CallInput (..)
  , defaultCallInput
  , CallResult (..)
  , runCall
  , runCalls
  , CompiledModule
  , compileModule
  , runCompiled
  , runCompiledLazyVars
    -- * Tracing
  , compileTracedModule
  , runCompiledTraced
  , checkMappedOperands
  , checkChfParameters
  , parameterErrorDetail
  , ParamSource (..)
  , diagnosticBand
  , writeDiagnostics
  ) where

import Control.Monad.ST (runST)
import Data.Foldable (foldl')
import qualified Data.IntMap.Strict as IM
import Data.IntMap.Strict (IntMap)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Vector as V
import Data.Word (Word16, Word32)
import Stref.Checked
import Stref.Diagnostics
import Data.STRef (readSTRef, writeSTRef)
import Stref.Eval hiding (compileModule, compileTracedModule)
import qualified Stref.Eval as Eval
import Stref.Operands
import Stref.Policy
import Stref.Trace (Event (..), Tracer, decision, emit, newTracer, ruled)
import Stref.Types
import Stref.Values

-- | What outlives a module call: the operands, and (under @lifetime =
-- retained@) the data area, slot by slot.
data PlcState = PlcState
  { psMemory :: Memory
  , psRetained :: Maybe (IntMap Value)
  }
  deriving (Eq, Show)

initialPlcState :: PlcState
initialPlcState = PlcState emptyMemory Nothing

data CallInput = CallInput
  { ciInputs :: (Bool, Bool, Bool) -- ^ INPUT1..3 (MT-SIG-2)
  , ciChfIn :: [ChfArg] -- ^ CHF input parameters (F modules)
  , ciChfOut :: [ChfArg] -- ^ CHF output parameters (F modules)
  }
  deriving (Eq, Show)

defaultCallInput :: CallInput
defaultCallInput = CallInput (True, True, True) [] []

data CallResult = CallResult
  { crOutputs :: (Bool, Bool, Bool) -- ^ OUTPUT1..3 after the call
  , crError :: Maybe RuntimeError
  , crVars :: [(Text, Value)] -- ^ named variables at the end of the call (arrays element-wise: @P.V[3]@)
  , crSteps :: !Int -- ^ steps used of the budget
  , crExecuted :: !Bool -- ^ FALSE when INPUT1 was FALSE and the module did not run (MT-SIG-3)
  , crOverflow :: !Bool -- ^ INTERNAL_OVERFLOW at the end of the call
  }
  deriving (Eq, Show)

-- | Translate a module once for all its calls, under the policies and the
-- controller's configuration: the module's mapped cells and the diagnostic
-- band are the cells a call holds in machine words, and a mapped variable's
-- place among them is found during the translation.
compileModule :: Policies -> PlcConfig -> CModule -> CompiledModule
compileModule pol cfg cm = Eval.compileModule pol (moduleCells cfg cm) cm

-- | 'compileModule' with tracing on, for 'runCompiledTraced'.
compileTracedModule :: Policies -> PlcConfig -> CModule -> CompiledModule
compileTracedModule pol cfg cm = Eval.compileTracedModule pol (moduleCells cfg cm) cm

moduleCells :: PlcConfig -> CModule -> CellSlots
moduleCells cfg cm = cellSlots (mappedCells (cmMapped cm) ++ bandCells cfg)

-- | Run several calls in sequence, each on the state the previous one left.
runCalls :: Policies -> PlcConfig -> CModule -> [CallInput] -> PlcState -> (PlcState, [CallResult])
runCalls pol cfg cm inputs st0 = go st0 inputs
  where
    compiled = compileModule pol cfg cm
    go st [] = (st, [])
    go st (ci : rest) =
      let (st', r) = runCompiled pol cfg cm compiled ci st
          (stN, rs) = go st' rest
       in (stN, r : rs)

-- | Run one module call. The diagnostic band is written into the memory.
runCall :: Policies -> PlcConfig -> CModule -> CallInput -> PlcState -> (PlcState, CallResult)
runCall pol cfg cm = runCompiled pol cfg cm (compileModule pol cfg cm)

-- | 'runCall' with a module translated beforehand by 'compileModule' under
-- the same policies (for many calls of one module). Applied to its first
-- four arguments, it checks the mapped operands once for all the calls.
runCompiled :: Policies -> PlcConfig -> CModule -> CompiledModule -> CallInput -> PlcState -> (PlcState, CallResult)
runCompiled = runCompiledWith True

-- | 'runCompiled' whose 'crVars' are read from the call's final state only
-- when they are looked at: cheaper when only some calls are observed (the
-- command line reports the last call's), but a result kept unobserved keeps
-- that state alive.
runCompiledLazyVars :: Policies -> PlcConfig -> CModule -> CompiledModule -> CallInput -> PlcState -> (PlcState, CallResult)
runCompiledLazyVars = runCompiledWith False

runCompiledWith :: Bool -> Policies -> PlcConfig -> CModule -> CompiledModule -> CallInput -> PlcState -> (PlcState, CallResult)
runCompiledWith eagerVars pol cfg cm compiled =
  -- an untraced translation's tracer is never told anything
  runCompiledTracing (\st r _ -> (st, r)) eagerVars pol cfg cm compiled (newTracer False)

-- | 'runCompiled' for a module translated by 'compileTracedModule': the
-- events of the call are added to the tracer, with the runtime error that
-- ended it (and the rule that raised it).
runCompiledTraced :: Policies -> PlcConfig -> CModule -> CompiledModule -> Tracer -> CallInput -> PlcState -> (PlcState, CallResult, Tracer)
runCompiledTraced = runCompiledTracing (,,) True

-- | A call, whose state, result and tracer are given to @ended@. Inlined,
-- with 'runChecked': for an untraced call the tracer is dropped where it is
-- built, and what does not depend on the call is computed once, outside
-- the call's closure (as when 'runChecked' had a single caller).
runCompiledTracing :: (PlcState -> CallResult -> Tracer -> a) -> Bool -> Policies -> PlcConfig -> CModule -> CompiledModule -> Tracer -> CallInput -> PlcState -> a
{-# INLINE runCompiledTracing #-}
runCompiledTracing ended eagerVars pol cfg cm compiled = case callSetup pol cfg cm compiled of
  CallSetup mappedChecked noParameters table band bandKeyed initialiseData -> \tracer ci st ->
    let (input1, _, _) = ciInputs ci
        checks = do
          mappedChecked
          -- no CHF arguments (every call of a P module): the same answer each time
          case (ciChfIn ci, ciChfOut ci) of
            ([], []) -> noParameters
            (ins, outs) -> checkChfParameters (pErrorLineBeforeStart pol) cfg (cmProgram cm) ins outs
     in runChecked ended eagerVars pol cm compiled table initialiseData band bandKeyed input1 checks tracer ci st

-- | What does not depend on the call, computed once for all the calls of a
-- module: the checks of the mapped operands and of an empty CHF parameter
-- list, the table of the cells held in machine words during a call (the
-- mapped ones and the diagnostic band), the band's cells and the translated
-- initialisation of the data area. (The builder is not inlined: GHC would
-- otherwise move this work into the function of the call.)
data CallSetup = CallSetup
  !(Either RuntimeError ())
  !(Either RuntimeError [ParamSource])
  !CellSlots
  ![Cell]
  ![(Cell, Int, Word32)] -- ^ the band's cells, their slots in the table, their patterns after a call without error
  (forall s. Exec s ())

callSetup :: Policies -> PlcConfig -> CModule -> CompiledModule -> CallSetup
{-# NOINLINE callSetup #-}
callSetup pol cfg cm compiled =
  CallSetup
    (checkMappedOperands lineBefore cfg (cmMapped cm))
    (checkChfParameters lineBefore cfg prog [] [])
    table
    band
    [(c, lookupSlot table (cellKey c), bandPattern x) | (c, x) <- zip band noErrorBand]
    initialiseData
  where
    prog = cmProgram cm
    lineBefore = pErrorLineBeforeStart pol -- A2
    band = bandCells cfg
    -- the table the module was translated against ('compileModule')
    table = cmCellSlots compiled
    -- the initialisation of the data area, translated once; the machine's
    -- data area starts at the type defaults whenever it is initialised (no
    -- retained slots then), so a variable there without an initialiser
    -- needs no write
    initialiseData :: Exec s ()
    initialiseData = do
      mapM_ initVar (filter needsWrite (map (`VarInit` Nothing) (cpOutputs prog))) -- A21
      mapM_ initVar (filter needsWrite (cmInits cm))
    needsWrite vi = case (varHome (viVar vi), viInit vi) of
      (Data _, Nothing) -> False
      _ -> True

{-# INLINE runChecked #-}
runChecked :: (PlcState -> CallResult -> Tracer -> a) -> Bool -> Policies -> CModule -> CompiledModule -> CellSlots -> (forall s. Exec s ()) -> [Cell] -> [(Cell, Int, Word32)] -> Bool -> Either RuntimeError [ParamSource] -> Tracer -> CallInput -> PlcState -> a
runChecked ended eagerVars pol cm compiled table initialiseData band bandKeyed input1 checks tracer ci st
  | not input1 =
      -- MT-SIG-3: the module does not run; the outputs of the instruction
      -- stay off and nothing else changes (not even the diagnostics)
      ended st (CallResult (False, False, False) Nothing [] 0 False False) (told (Rule 0 (decision ["MT-SIG-3"] "INPUT1 is FALSE: the module does not run")) tracer)
  | otherwise = case checks of
      Left err ->
        let sn =
              Snapshot
                { snData = V.imap (\k d -> IM.findWithDefault d k retainedData) (cmDataDefaults compiled)
                , snMemory = psMemory st
                , snOutputs = (False, False, False)
                , snOverflow = False
                , snSteps = 0
                }
         in withTracer (failure err tracer) (finish True (psRetained st) (Left err) sn)
      Right sources -> runST (runBody sources)
  where
    withTracer tr (st', r) = ended st' r tr
    -- only a traced translation's tracer is told anything
    told ev tr = if cmTraced compiled then emit ev tr else tr
    -- a runtime error, the rule that raised it, and for the limits the
    -- rule that set them (told after the error, which ends every loop,
    -- so that they are never left out of a summarised loop)
    failure err tr =
      let code = reCode err
          limits
            | code == errExecutionTime = [ruled ["MT-EXEC-7"] "step-budget" ("the budget of " <> T.pack (show (pStepBudget pol)) <> " steps is used up")]
            | code == errCallDepth = [decision ["MT-POU-9", "MT-LIM-1"] "at most 16 nested function calls"]
            | otherwise = []
          failed = told (Failure (reLine err) (errorRule code) (T.pack (show code) <> ", " <> describeErrorCode code)) tr
       in foldl (\t d -> told (Rule (reLine err) d) t) failed limits
    runBody sources = do
      m <- newMachine compiled table retainedData (psMemory st) (True, False, False) -- MT-SIG-4, A5
      mapM_ (`writeSTRef` tracer) (mTrace m)
      r <- unExec (prepare sources >> cmBody compiled) env m
      tracer' <- maybe (pure tracer) readSTRef (mTrace m)
      let tracerN = case r of
            Done _ -> tracer'
            Failed err -> failure err tracer'
      case copyPairs sources of
        [] -> do
          -- nothing to copy back (P modules): the band is written in the
          -- machine, where its cells are held
          case r of
            Done _ -> mapM_ (\(c, k, w) -> writeMachineCell m c k w) bandKeyed
            Failed err -> mapM_ (\((c, k, _), x) -> writeMachineCell m c k (bandPattern x)) (zip bandKeyed (errorBand err))
          sn <- snapshot m
          pure $ withTracer tracerN $ case r of
            Done _ -> finish False (keep sn) (Right ()) sn
            Failed err -> finish False (keep sn) (Left err) sn
        _ -> do
          sn <- snapshot m
          pure $ withTracer tracerN $ case r of
            Done _ -> finish True (keep sn) (Right ()) (copyBack sources sn)
            Failed err -> finish True (keep sn) (Left err) sn
    env = Env (ciInputs ci) 0
    prog = cmProgram cm
    firstCall = case psRetained st of
      Nothing -> True
      Just _ -> False
    retainedData = case (pLifetime pol, psRetained st) of
      (Retained, Just d) -> d
      _ -> IM.empty
    initialise = pLifetime pol == PerCall || firstCall
    prepare sources = do
      if initialise then initialiseData else pure ()
      -- VAR_INPUT and VAR_IN_OUT: copied in on every call (MT-PARAM-3, MT-PARAM-5)
      case zip (cpInputs prog ++ cpInOuts prog) sources of
        [] -> pure () -- no parameters (P modules)
        params -> getMemory >>= \memory -> mapM_ (copyIn memory) params
    copyIn memory (v, src) =
      mapM_ (\k -> writeElement v k (sourceRead memory src (varBasicType v) k)) [0 .. varElements v - 1]
    -- MT-PARAM-5: VAR_IN_OUT back to their operands, then VAR_OUTPUT to
    -- the CHF outputs (so an output wins when both name one operand)
    copyPairs sources =
      zip (cpInOuts prog) (drop (length (cpInputs prog)) sources)
        ++ zip (cpOutputs prog) (outputSources (ciChfOut ci))
    copyBack sources m =
      let writeBack mem (v, src) =
            foldl'
              (\mm k -> sourceWrite src k (readNow m v k) mm)
              mem
              [0 .. varElements v - 1]
       in m {snMemory = foldl' writeBack (snMemory m) (copyPairs sources)}
    readNow m v k = snapshotElement env m v k
    keep sn = case pLifetime pol of
      Retained -> Just (IM.fromDistinctAscList (zip [0 ..] (V.toList (snData sn))))
      PerCall -> Nothing
    -- the band is written here unless it was in the machine
    finish withBand retained result sn =
      let (values, err, outs) = case result of
            Right () -> (noErrorBand, Nothing, snOutputs sn)
            Left e -> (errorBand e, Just e, clearOutput1 (snOutputs sn))
          mem' = if withBand then writeBand band values (snMemory sn) else snMemory sn
          sn' = sn {snMemory = mem', snOutputs = outs}
          st' =
            PlcState
              { psMemory = mem'
              , psRetained = retained
              }
          vars = namedValues env sn' cm
       in -- the observed values are taken now, so that a long run of calls
          -- does not keep every call's machine alive
          (if eagerVars then forceVars vars else ()) `seq` (st', CallResult outs err vars (snSteps sn') True (snOverflow sn'))
    clearOutput1 (_, b, c) = (False, b, c)

forceVars :: [(Text, Value)] -> ()
forceVars = foldr (\(_, v) rest -> v `seq` rest) ()

-- | The values of the observable variables (arrays element by element).
namedValues :: Env -> Snapshot -> CModule -> [(Text, Value)]
namedValues env m cm = concatMap one (cmNamed cm)
  where
    one (name, v) = case varType v of
      Basic _ -> [(name, get v 0)]
      Array lo _ _ ->
        [ (name <> "[" <> T.pack (show (lo + toInteger k)) <> "]", get v k)
        | k <- [0 .. varElements v - 1]
        ]
    get v k = snapshotElement env m v k

-- | The five diagnostic operands (MT-DIAG-2).
diagnosticBand :: PlcConfig -> [Operand]
diagnosticBand cfg = [OpSimple KM (plcDiagnostics cfg + i) | i <- [0 .. 4]]

writeDiagnostics :: PlcConfig -> [Int] -> Memory -> Memory
writeDiagnostics cfg = writeBand (bandCells cfg)

bandCells :: PlcConfig -> [Cell]
bandCells cfg = map operandCell (diagnosticBand cfg)

-- | Write the band's values as INT into its cells.
writeBand :: [Cell] -> [Int] -> Memory -> Memory
writeBand cells band mem = foldl' write mem (zip cells band)
  where
    -- the INT's 16-bit pattern; a cell already written with it is left as
    -- it is, the memory being the same (most calls write the band of the
    -- call before)
    write m (cell, x) =
      let bits = bandPattern x
       in case lookupCell m cell of
            Just old | old == bits -> m
            _ -> writeCell cell bits m

-- | A band value's pattern: the INT's 16 bits.
bandPattern :: Int -> Word32
bandPattern x = fromIntegral (fromIntegral x :: Word16)

--------------------------------------------------------------------------------
-- Checks before the first statement

-- | MT-MAP-8, MT-MAP-10: every mapped operand, every element of a mapped
-- array, must be declared; the first one that is not, in declaration order,
-- is the error: 2000 (simple operand: kind code, address), 2001 (table not
-- declared: kind code, table), 2002 (position not declared: kind code,
-- table, position).
checkMappedOperands :: Int -> PlcConfig -> [Var] -> Either RuntimeError ()
checkMappedOperands line cfg vars = mapM_ checkCell (mappedCells vars)
  where
    checkCell c
      | cellDeclared cfg c = Right ()
      | otherwise = Left (undeclaredCell line cfg c)

-- | The cells of the mapped variables, every element of an array, in
-- declaration order.
mappedCells :: [Var] -> [Cell]
mappedCells vars =
  [ operandCell (elementOperand op k)
  | v <- vars
  , Mapped op <- [varHome v]
  , k <- [0 .. varElements v - 1]
  ]

undeclaredCell :: Int -> PlcConfig -> Cell -> RuntimeError
undeclaredCell line cfg c = case c of
  CellSimple _ a -> RuntimeError errOperandNotDeclared line (code, a, 0) -- MT-ERR-2000
  CellTable k a p
    | M.member (k, a) (plcTables cfg) -> RuntimeError errTablePositionNotDeclared line (code, a, p) -- MT-ERR-2002
    | otherwise -> RuntimeError errTableNotDeclared line (code, a, 0) -- MT-ERR-2001
  where
    code = operandKindCode c

-- | Where a program parameter's value comes from, or goes to.
data ParamSource
  = FromOperand Operand -- ^ a simple operand or table position; arrays: the first element
  | FromConstant Value -- ^ a constant operand, already of the parameter's type
  deriving (Eq, Show)

-- | MT-PARAM-3..7: the CHF arguments against the program's parameters.
-- Inputs are VAR_INPUT then VAR_IN_OUT, outputs the VAR_OUTPUT; the first
-- problem in the order (input count, output count, inputs, outputs) is the
-- error; complement 1 is the 1-based parameter number. On success: the
-- source of every input parameter.
checkChfParameters :: Int -> PlcConfig -> CProgram -> [ChfArg] -> [ChfArg] -> Either RuntimeError [ParamSource]
checkChfParameters line cfg prog ins outs
  | length ins /= length inParams = Left (runtimeError errInputCount line) -- MT-ERR-2009
  | length outs /= length (cpOutputs prog) = Left (runtimeError errOutputCount line) -- MT-ERR-2010
  | otherwise = do
      srcs <- sequence (zipWith3 checkInput [1 ..] inParams ins)
      _ <- sequence (zipWith3 checkOutput [1 ..] (cpOutputs prog) outs)
      pure srcs
  where
    inParams = [(v, True) | v <- cpInputs prog] ++ [(v, False) | v <- cpInOuts prog]
    param code n = Left (RuntimeError code line (n, 0, 0))
    checkInput :: Int -> (Var, Bool) -> ChfArg -> Either RuntimeError ParamSource
    checkInput n (v, isInput) arg = case arg of
      ChfConstant kind r
        -- MT-PARAM-6 (2), MT-PARAM-7: constants only to VAR_INPUT scalars
        | not isInput || isArray v || not (constantFits kind (varBasicType v)) -> param errInputParameter n
        | otherwise -> maybe (param errConstantValue n) (Right . FromConstant) (constantValue (varBasicType v) r)
      _ -> operandParam errInputParameter errInputOperandNotDeclared errInputArrayTooShort n v arg
    checkOutput n v arg = case arg of
      ChfConstant {} -> param errOutputParameter n
      _ -> operandParam errOutputParameter errOutputOperandNotDeclared errOutputArrayTooShort n v arg
    operandParam eType eDecl eShort n v arg = case (varType v, arg) of
      -- MT-PARAM-6 (3): no partial operands; (4): tables only to arrays
      (_, ChfOperand OpBit {}) -> param eType n
      (Basic t, ChfOperand op@(OpSimple _ _))
        | not (compatibleType op t) -> param eType n -- MT-PARAM-6 (1), Table 4-8
        | not (cellDeclared cfg (operandCell op)) -> param eDecl n -- MT-PARAM-6 (6)
        | otherwise -> Right (FromOperand op)
      (Basic _, _) -> param eType n
      -- MT-PARAM-6 (5), (7): an array takes a block of simple operands or
      -- (part of) a table, declared over its whole size
      (Array _ _ t, ChfOperand op@(OpSimple _ _))
        | not (compatibleType op t) -> param eType n
        | all (cellDeclared cfg . operandCell . elementOperand op) [0 .. varElements v - 1] -> Right (FromOperand op)
        | otherwise -> param eDecl n
      (Array _ _ t, ChfOperand op@(OpTablePos k a p)) -> tableParam eType eDecl eShort n v t k a p op
      (Array _ _ t, ChfTable k a) -> tableParam eType eDecl eShort n v t k a 0 (OpTablePos k a 0)
      (Array {}, ChfConstant {}) -> param eType n
    tableParam eType eDecl eShort n v t k a p op
      | not (compatibleType op t) = param eType n
      | not (M.member (k, a) (plcTables cfg)) || not (cellDeclared cfg (CellTable k a p)) = param eDecl n
      | not (cellDeclared cfg (CellTable k a (p + varElements v - 1))) = param eShort n -- MT-ERR-2011, 2012
      | otherwise = Right (FromOperand op)
    isArray v = case varType v of
      Array {} -> True
      Basic _ -> False

-- | For the user, what a CHF parameter error of 'checkChfParameters' is
-- about: the counts behind 2009 and 2010, the parameter that the first
-- complement of 2003 to 2006, 2011 and 2012 numbers. (The controller shows
-- only the code and the complements.)
parameterErrorDetail :: CProgram -> Int -> Int -> RuntimeError -> Maybe Text
parameterErrorDetail prog givenIns givenOuts (RuntimeError code _ (n, _, _))
  | code == errInputCount = Just (counted "input" inParams <> ", the call gives " <> tshow givenIns)
  | code == errOutputCount = Just (counted "output" (cpOutputs prog) <> ", the call gives " <> tshow givenOuts)
  | code `elem` [errInputParameter, errInputOperandNotDeclared, errConstantValue, errInputArrayTooShort] = numbered "input" inParams
  | code `elem` [errOutputParameter, errOutputOperandNotDeclared, errOutputArrayTooShort] = numbered "output" (cpOutputs prog)
  | otherwise = Nothing
  where
    inParams = cpInputs prog ++ cpInOuts prog
    counted what vs =
      cpName prog <> " has " <> tshow (length vs) <> " " <> what <> " parameter" <> (if length vs == 1 then "" else "s")
        <> (if null vs then "" else " (" <> T.intercalate ", " (map varName vs) <> ")")
    numbered what vs = case drop (n - 1) vs of
      v : _ | n >= 1 -> Just (what <> " parameter " <> tshow n <> " is " <> varName v)
      _ -> Nothing
    tshow :: Int -> Text
    tshow = T.pack . show

-- | An integer constant (%KM, %KI) goes to any integer or bit-string
-- parameter, a real constant (%KF) to a REAL one; whether the value fits the
-- parameter is the separate check of 2008 (MT-PARAM-7: the constant is
-- measured against the parameter's size, not against its own kind).
constantFits :: ConstKind -> BasicType -> Bool
constantFits kind t = case kind of
  KMConst -> integral
  KIConst -> integral
  KFConst -> t == REAL
  where
    integral = t `elem` [USINT, BYTE, INT, WORD, DINT, DWORD]

-- | MT-PARAM-7: the constant's value must fit the parameter (else 2008): an
-- integer within the type's range, or a REAL within the binary32 range.
constantValue :: BasicType -> Rational -> Maybe Value
constantValue t r = case intRange t of
  Just (lo, hi)
    | fromInteger n == r && n >= lo && n <= hi -> Just (integerToValue t n)
    | otherwise -> Nothing
    where
      n = truncate r
  Nothing
    | t == REAL && abs r <= toRational (3.4028235e38 :: Float) -> Just (VReal (fromRational r))
    | otherwise -> Nothing

sourceRead :: Memory -> ParamSource -> BasicType -> Int -> Value
sourceRead mem src t k = case src of
  FromConstant v -> v
  FromOperand op -> readOperand mem (elementOperand op k) t

sourceWrite :: ParamSource -> Int -> Value -> Memory -> Memory
sourceWrite src k v mem = case src of
  FromConstant _ -> mem
  FromOperand op -> writeOperand (elementOperand op k) v mem

outputSources :: [ChfArg] -> [ParamSource]
outputSources = map $ \case
  ChfOperand op -> FromOperand op
  ChfTable k a -> FromOperand (OpTablePos k a 0)
  ChfConstant _ _ -> FromConstant (VBool False)
