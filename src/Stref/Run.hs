-- | The pure pipeline from source text to results: parse, check, then run a
-- number of module calls on a simulated controller. The command line and the
-- corpus engine are thin layers over this module.
module Stref.Run
  ( -- * Setting operands
    Setting (..)
  , applySetting
  , applySettings
    -- * Running
  , RunSetup (..)
  , defaultRunSetup
  , CallSpec (..)
  , defaultCallSpec
  , RunFailure (..)
  , renderRunFailure
  , RunOutcome (..)
  , compileSource
  , runModule
  , CallStream (..)
  , streamModule
  , runSource
    -- * Tracing
  , runModuleTraced
    -- * Observing
  , observeOperand
  , cellOperand
  , changedCells
    -- * Snippets (@stref eval@)
  , Snippet (..)
  , SnippetResult (..)
  , evalSnippet
  , evalSnippetCalls
  , evalSnippetTraced
  ) where

import Data.Bits (shiftL)
import Data.List (find)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import Stref.Check (checkModule)
import Stref.Checked
import Stref.Conversions (ConversionFunction (..), lookupConversionFunction)
import Stref.Execution
import Stref.Operands
import Stref.Policy
import Stref.Syntax (Expr (..), Ident (..), Module, Pos)
import Stref.Syntax.Parser (parseExpression, parseModule)
import Stref.Trace (Event (..), Tracer, emit, newTracer, tracerEvents)
import Stref.Types
import Stref.Values
import Stref.Verification

-- | A value written into an operand from outside (the corpus' @plc.init@ and
-- @set@, the command line's @--set@).
data Setting
  = SetInt Integer -- ^ a bit pattern, read as signed or unsigned
  | SetBool Bool -- ^ for a bit operand
  | SetReal Float -- ^ for %F and %TF
  deriving (Eq, Show)

-- | Write a setting into an operand, or say why it does not fit.
applySetting :: Operand -> Setting -> Memory -> Either Text Memory
applySetting o s mem = case (o, s) of
  (OpBit {}, SetBool b) -> Right (writeOperand o (VBool b) mem)
  (OpBit {}, SetInt n)
    | n == 0 || n == 1 -> Right (writeOperand o (VBool (n == 1)) mem)
  (OpBit {}, _) -> Left (name <> " is a bit: it takes TRUE or FALSE")
  (_, SetBool _) -> Left (name <> " is not a bit: it takes a number")
  (_, SetReal r)
    | isReal -> Right (writeOperand o (VReal r) mem)
    | otherwise -> Left (name <> " holds an integer, not " <> T.pack (show r))
  (_, SetInt n)
    | isReal -> Right (writeOperand o (VReal (fromInteger n)) mem)
    | n >= negate (half width) && n < 2 * half width -> Right (writeCell cell (fromInteger (n `mod` (2 * half width))) mem)
    | otherwise -> Left ("the value " <> T.pack (show n) <> " does not fit in " <> name <> " (" <> T.pack (show width) <> " bits)")
  where
    cell = operandCell o
    width = cellWidth cell
    half w = 1 `shiftL` (w - 1) :: Integer
    name = renderOperand o
    isReal = case cell of
      CellSimple KF _ -> True
      CellTable TF _ _ -> True
      _ -> False

applySettings :: [(Operand, Setting)] -> Memory -> Either Text Memory
applySettings settings mem = foldl (\acc (o, s) -> acc >>= applySetting o s) (Right mem) settings

-- | The natural reading of an operand: a bit as BOOL, %E/%S/%A as USINT,
-- %M/%TM as INT, %I/%TI as DINT, %F/%TF as REAL.
observeOperand :: Memory -> Operand -> Value
observeOperand mem o = readOperand mem o t
  where
    t = case o of
      OpBit {} -> BOOL
      _ -> case operandCell o of
        CellSimple k _ -> case k of
          KM -> INT
          KI -> DINT
          KF -> REAL
          _ -> USINT
        CellTable k _ _ -> case k of
          TM -> INT
          TI -> DINT
          TF -> REAL

cellOperand :: Cell -> Operand
cellOperand = \case
  CellSimple k a -> OpSimple k a
  CellTable k a p -> OpTablePos k a p

-- | The declared cells whose contents differ between two memories.
changedCells :: PlcConfig -> Memory -> Memory -> [(Cell, Word32, Word32)]
changedCells cfg before after =
  [ (c, old, new)
  | c <- cellCells cfg
  , let old = readCell before c
        new = readCell after c
  , old /= new
  ]

-- | How to run a module.
data RunSetup = RunSetup
  { rsPolicies :: Policies
  , rsPlc :: PlcConfig
  , rsKind :: ModuleKind
  , rsInit :: [(Operand, Setting)] -- ^ operand values before the first call
  }

defaultRunSetup :: RunSetup
defaultRunSetup = RunSetup mastertoolXE defaultPlcConfig ProcedureModule []

-- | One module call: the inputs, operands written just before it, and the
-- CHF parameters (F modules).
data CallSpec = CallSpec
  { csInputs :: (Bool, Bool, Bool)
  , csSet :: [(Operand, Setting)]
  , csChfIn :: [ChfArg]
  , csChfOut :: [ChfArg]
  }
  deriving (Eq, Show)

defaultCallSpec :: CallSpec
defaultCallSpec = CallSpec (True, True, True) [] [] []

data RunFailure
  = SyntaxError VerificationError
  | Rejected [VerificationError]
  | BadSetting Text
  deriving (Eq, Show)

-- | A message for a failure; verification errors with the source line and a
-- caret.
renderRunFailure :: FilePath -> Text -> RunFailure -> Text
renderRunFailure file source = \case
  SyntaxError e -> renderError file source e
  Rejected es -> renderErrors file source es
  BadSetting msg -> msg <> "\n"

data RunOutcome = RunOutcome
  { roModule :: CModule
  , roInitial :: PlcState -- ^ after the initial settings, before the first call
  , roResults :: [CallResult] -- ^ one per call
  , roFinal :: PlcState
  }

-- | Parse and check.
compileSource :: Policies -> ModuleKind -> FilePath -> Text -> Either RunFailure CModule
compileSource pol kind file src = do
  m <- either (Left . SyntaxError) Right (parseModule pol file src)
  checked pol kind m

checked :: Policies -> ModuleKind -> Module Pos -> Either RunFailure CModule
checked pol kind m = either (Left . Rejected) Right (checkModule pol kind m)

-- | Run the calls of a checked module, in order. Every operand a call
-- writes is checked to be declared before the first call.
runModule :: RunSetup -> CModule -> [CallSpec] -> Either RunFailure RunOutcome
runModule setup cm calls = do
  mapM_ (declared setup) (rsInit setup ++ concatMap csSet calls)
  (st0, stream) <- streamModule setup cm calls
  let collect = \case
        CallsDone final -> Right ([], final)
        CallsFailed failure -> Left failure
        -- each result's variables are read now, so that the kept results do
        -- not keep every call's final state alive
        CallStep r _ rest -> foldr (seq . snd) () (crVars r) `seq` (\(rs, final) -> (r : rs, final)) <$> collect rest
  (results, final) <- collect stream
  pure (RunOutcome cm st0 results final)

-- | The results of a run as the calls happen: consumed once, in order, a
-- run of any length needs constant memory (the command line's @--calls@).
data CallStream
  = CallStep !CallResult PlcState CallStream -- ^ a call's result and the state it left
  | CallsDone !PlcState -- ^ the state after the last call
  | CallsFailed RunFailure -- ^ a call's operand setting does not fit

-- | 'runModule' one call at a time: the state before the first call and the
-- calls' results. The operands a call writes are checked when its turn
-- comes.
streamModule :: RunSetup -> CModule -> [CallSpec] -> Either RunFailure (PlcState, CallStream)
streamModule setup cm calls = do
  mapM_ (declared setup) (rsInit setup)
  mem0 <- either (Left . BadSetting) Right (applySettings (rsInit setup) emptyMemory)
  let st0 = initialPlcState {psMemory = mem0}
      go !st = \case
        [] -> CallsDone st
        c : rest -> case callSettings setup c (psMemory st) of
          Left failure -> CallsFailed failure
          Right mem ->
            let ci = CallInput (csInputs c) (csChfIn c) (csChfOut c)
                (st', r) = call ci st {psMemory = mem}
             in st' `seq` CallStep r st' (go st' rest)
  pure (st0, go st0 calls)
  where
    -- translated and checked once for all the calls
    call = runCompiledLazyVars (rsPolicies setup) (rsPlc setup) cm (compileModule (rsPolicies setup) (rsPlc setup) cm)

-- | The memory with the operands a call writes before it runs.
callSettings :: RunSetup -> CallSpec -> Memory -> Either RunFailure Memory
callSettings setup c mem = case csSet c of
  [] -> Right mem
  sets -> traverse (declared setup) sets >> either (Left . BadSetting) Right (applySettings sets mem)
-- inlined: a call that sets nothing then builds no Right
{-# INLINE callSettings #-}

-- | 'runModule' with tracing on (docs/trace.md): the outcome, which is the
-- untraced run's, and the events of every call, each call's after a
-- 'Cycle' event counting from 1. With @True@ every loop iteration is kept,
-- else only the first few of each loop ('Stref.Trace.keptIterations').
runModuleTraced :: Bool -> RunSetup -> CModule -> [CallSpec] -> Either RunFailure (RunOutcome, [Event])
runModuleTraced everyIteration setup cm calls = do
  mapM_ (declared setup) (rsInit setup ++ concatMap csSet calls)
  mem0 <- either (Left . BadSetting) Right (applySettings (rsInit setup) emptyMemory)
  let st0 = initialPlcState {psMemory = mem0}
  (results, final, tracer) <- go st0 (newTracer everyIteration) (zip [1 ..] calls)
  pure (RunOutcome cm st0 results final, tracerEvents tracer)
  where
    pol = rsPolicies setup
    -- translated and checked once for all the calls
    call = runCompiledTraced pol (rsPlc setup) cm (compileTracedModule pol (rsPlc setup) cm)
    go :: PlcState -> Tracer -> [(Int, CallSpec)] -> Either RunFailure ([CallResult], PlcState, Tracer)
    go st tracer = \case
      [] -> Right ([], st, tracer)
      (n, c) : rest -> do
        mem <- callSettings setup c (psMemory st)
        let (st', r, tracer') = call (emit (Cycle n) tracer) (CallInput (csInputs c) (csChfIn c) (csChfOut c)) st {psMemory = mem}
        (rs, final, tracerN) <- go st' tracer' rest
        pure (r : rs, final, tracerN)

declared :: RunSetup -> (Operand, Setting) -> Either RunFailure ()
declared setup (o, _)
  | cellDeclared (rsPlc setup) (operandCell o) = Right ()
  | otherwise = Left (BadSetting (renderOperand o <> " is not declared in the controller's configuration"))

-- | Parse, check and run.
runSource :: RunSetup -> FilePath -> Text -> [CallSpec] -> Either RunFailure RunOutcome
runSource setup file src calls = do
  cm <- compileSource (rsPolicies setup) (rsKind setup) file src
  runModule setup cm calls

--------------------------------------------------------------------------------
-- Snippets

-- | What @stref eval@ ran: statements (with optional VAR blocks) or a bare
-- expression, and the program text it was wrapped into.
data Snippet = Snippet
  { snExpression :: Bool
  , snSource :: Text -- ^ the wrapped program
  }
  deriving (Eq, Show)

data SnippetResult = SnippetResult
  { srSnippet :: Snippet
  , srType :: Maybe BasicType -- ^ of a bare expression
  , srResult :: CallResult
  }
  deriving (Eq, Show)

-- | The name of the variable that receives a bare expression's value.
resultName :: Text
resultName = "EVAL_RESULT"

-- | Run a snippet once as a P module with the default controller. The
-- wrapper keeps the snippet's first line on line 1, so line numbers in
-- messages are the snippet's own.
--
-- A bare expression has no declared type, so it is assigned to a result
-- variable whose type is found by trying: a call of a conversion function
-- has its target type; otherwise the first of INT, DINT, DWORD, REAL, BOOL,
-- WORD, BYTE, USINT that the checker accepts without converting the value
-- (literals take the type of their context, decision A11), or failing that
-- the first it accepts at all.
evalSnippet :: Policies -> Text -> Either (Text, RunFailure) SnippetResult
evalSnippet = evalSnippetCalls 1

-- | 'evalSnippet' over several calls (at least one): its locals start again
-- at each call (MT-EXEC-9), the operands it maps keep their values; the
-- result is the last call's.
evalSnippetCalls :: Int -> Policies -> Text -> Either (Text, RunFailure) SnippetResult
evalSnippetCalls calls pol snippet = do
  (sn, t, cm) <- snippetModule pol snippet
  let compiled = compileModule pol defaultPlcConfig cm
  Right (SnippetResult sn t (lastOf calls (\_ st -> runCompiled pol defaultPlcConfig cm compiled defaultCallInput st) initialPlcState))

-- | 'evalSnippetCalls' with tracing on: the result and the events of its
-- calls (every loop iteration kept with @True@).
evalSnippetTraced :: Bool -> Int -> Policies -> Text -> Either (Text, RunFailure) (SnippetResult, [Event])
evalSnippetTraced everyIteration calls pol snippet = do
  (sn, t, cm) <- snippetModule pol snippet
  let compiled = compileTracedModule pol defaultPlcConfig cm
      -- several calls are told apart as a run's are, one call is not
      numbered i tracer = if calls > 1 then emit (Cycle i) tracer else tracer
      call i (st, tracer) =
        let (st', r, tracer') = runCompiledTraced pol defaultPlcConfig cm compiled (numbered i tracer) defaultCallInput st
         in ((st', tracer'), (r, tracer'))
      (r, traced) = lastOf calls call (initialPlcState, newTracer everyIteration)
  Right (SnippetResult sn t r, tracerEvents traced)

-- | The result of the last of n calls (at least one), each call given its
-- number from 1 and the state the one before left.
lastOf :: Int -> (Int -> s -> (s, r)) -> s -> r
lastOf n call = go 1
  where
    go !i !st =
      let (st', r) = call i st
       in if i >= n then r else go (i + 1) st'

-- | The program a snippet is wrapped into, checked, and a bare
-- expression's type.
snippetModule :: Policies -> Text -> Either (Text, RunFailure) (Snippet, Maybe BasicType, CModule)
snippetModule pol snippet = case parseExpression pol snippet of
  Right e -> do
    let conversionTarget = case e of
          ECall _ (Ident f) _ -> case lookupConversionFunction f of
            Just (Explicit _ t) -> Just t
            Just (AnyTo t) -> Just t
            Nothing -> Nothing
          _ -> Nothing
        order = maybe priority (: priority) conversionTarget
        accepted = [(t, src, cm) | t <- order, let src = wrapExpression t, Right cm <- [compileSource pol ProcedureModule "<eval>" src]]
        unconverted (t, _, cm) = case cpBody (cmProgram cm) of
          [SAssign _ _ (CConv _ to _)] -> to /= t
          _ -> True
        chosen = case (conversionTarget, accepted) of
          (Just t, a@(t', _, _) : _) | t == t' -> Just a
          _ -> case filter unconverted accepted of
            a : _ -> Just a
            [] -> find (const True) accepted
    case chosen of
      Just (t, src, cm) -> Right (Snippet True src, Just t, cm)
      Nothing ->
        -- report the errors of the most common reading (an INT result)
        let src = wrapExpression INT
         in Left (src, either id (const (Rejected [])) (compileSource pol ProcedureModule "<eval>" src))
  Left _ -> do
    let src = "PROGRAM EVAL " <> snippet <> "\nEND_PROGRAM\n"
    cm <- either (Left . (src,)) Right (compileSource pol ProcedureModule "<eval>" src)
    Right (Snippet False src, Nothing, cm)
  where
    priority = [INT, DINT, DWORD, REAL, BOOL, WORD, BYTE, USINT]
    wrapExpression t =
      "PROGRAM EVAL VAR " <> resultName <> " : " <> typeName t <> "; END_VAR " <> resultName <> " := " <> snippet <> "\n;\nEND_PROGRAM\n"
