-- | The reference engine: the project's own answer to a @stref-engine/1@
-- request, as a pure function. It parses and checks the source under the
-- request's policies and runs the module calls one after the other on one
-- controller state.
--
-- Every call runs, as a controller keeps scanning after a runtime error
-- (the error only ends the call that raised it, MT-DIAG-2); the verdict and
-- the reported error are those of the last call, like every other
-- observation.
module Stref.Engine
  ( referenceEngine
  , referenceTrace
  , requestPolicies
  , scalarToCellBits
  ) where

import Control.Monad (foldM)
import Data.Bits (testBit)
import Data.Char (toUpper)
import Data.List (minimumBy, sortOn)
import qualified Data.Map.Strict as M
import Data.Ord (comparing)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import Stref.Check (checkModule)
import Stref.Checked (ModuleKind (..))
import Stref.Conformance.Protocol
import Stref.Diagnostics (RuntimeError (..))
import Stref.Execution
import Stref.IEC.Engine (iecEngine, iecTrace)
import Stref.Trace (Event (..), emit, newTracer, tracerEvents)
import Stref.Operands
import Stref.Policy
import Stref.Syntax (Pos (..))
import Stref.Syntax.Parser (parseModule)
import Stref.Values
import Stref.Verification (VerificationError (..))

-- | The policies a request asks for: the dialect's preset, then the
-- request's choices, then the given overrides (those of @stref engine
-- --policy K=V@, which win over the request's).
requestPolicies :: [(Text, Text)] -> Request -> Either Text Policies
requestPolicies overrides rq = do
  preset <- maybe (Left ("unknown dialect '" <> rqDialect rq <> "'; known: " <> T.intercalate ", " (map fst presets))) Right (lookupPreset (rqDialect rq))
  foldM (\p (k, v) -> setPolicy k v p) preset (M.toList (rqPolicies rq) ++ overrides)

-- | Answer one request. Problems with the request itself (an unknown
-- protocol, dialect or policy, a malformed operand) give @unsupported@ with
-- the reason.
referenceEngine :: [(Text, Text)] -> Request -> Answer
referenceEngine overrides rq = either AnswerUnsupported id $ do
  if rqProtocol rq /= protocolVersion
    then Left ("protocol '" <> rqProtocol rq <> "' is not spoken here; this engine speaks " <> protocolVersion)
    else Right ()
  pol <- requestPolicies overrides rq
  case pModel pol of
    IecController -> Right (iecEngine pol rq)
    MasterToolController -> mastertoolEngine pol rq

-- | 'referenceEngine' with the trace of the run (@stref conformance
-- --explain@) and the policies it ran under.
referenceTrace :: [(Text, Text)] -> Request -> Either Text (Policies, Answer, [Event])
referenceTrace overrides rq = do
  pol <- requestPolicies overrides rq
  case pModel pol of
    IecController -> let (a, evs) = iecTrace False pol rq in Right (pol, a, evs)
    MasterToolController -> (\(a, evs) -> (pol, a, evs)) <$> mastertoolAnswer True pol rq

-- | The MasterTool XE controller's answer (a module called N times).
mastertoolEngine :: Policies -> Request -> Either Text Answer
mastertoolEngine pol rq = fst <$> mastertoolAnswer False pol rq

-- | The answer, and when traced the events of the calls.
mastertoolAnswer :: Bool -> Policies -> Request -> Either Text (Answer, [Event])
mastertoolAnswer traced pol rq = do
  kind <- case T.toUpper (rqModule rq) of
    "P" -> Right ProcedureModule
    "F" -> Right FunctionModule
    m -> Left ("module kind '" <> m <> "' is neither P nor F")
  diag <- case parseOperand (prDiagnostics (rqPlc rq)) of
    Right (OpSimple KM a) -> Right a
    _ -> Left ("the diagnostic band must start at a %M operand, not '" <> prDiagnostics (rqPlc rq) <> "'")
  let cfg = declareToConfig diag (prDeclare (rqPlc rq))
  chf <- traverse chfArgs (prChf (rqPlc rq))
  initial <- foldM writeScalar emptyMemory =<< sortedOperands (prInit (rqPlc rq))
  observed <- traverse (\t -> (t,) <$> parseOperand t) (obsOperands (rqObserve rq))
  calls <- traverse (\c -> (,) (callInputs c) <$> sortedOperands (callSet c)) (rqCalls rq)
  if null calls then Left "the request has no calls" else Right ()
  pure $ case parseModule pol (T.unpack (rqCase rq)) (rqSource rq) of
    Left e -> (rejected e, [])
    Right m -> case checkModule pol kind m of
      Left [] -> (AnswerRejected Nothing Nothing "the program was rejected", [])
      Left es -> (rejected (minimumBy (comparing vePos) es), [])
      Right cm ->
        let before st sets = st {psMemory = foldl (\acc (op, s) -> either (const acc) id (writeScalar acc (op, s))) (psMemory st) sets}
            input ins = CallInput ins (maybe [] fst chf) (maybe [] snd chf)
            step (st, _) (ins, sets) =
              let (st', res) = runCall pol cfg cm (input ins) (before st sets)
               in (st', Just res)
            -- the same calls on the traced translation (docs/trace.md)
            compiled = compileTracedModule pol cfg cm
            tracedStep (st, _, tr) (k, (ins, sets)) =
              let (st', res, tr') = runCompiledTraced pol cfg cm compiled (emit (Cycle k) tr) (input ins) (before st sets)
               in (st', Just res, tr')
            start = initialPlcState {psMemory = initial}
            answer final = maybe (AnswerUnsupported "the request has no calls") (observe (psMemory final) observed)
         in if traced
              then let (final, lastResult, tr) = foldl tracedStep (start, Nothing, newTracer False) (zip [1 ..] calls) in (answer final lastResult, tracerEvents tr)
              else let (final, lastResult) = foldl step (start, Nothing) calls in (answer final lastResult, [])
  where
    rejected (VerificationError k (Pos l _) msg) = AnswerRejected (Just l) (Just k) msg
    chfArgs (ChfRequest i o) = (,) <$> traverse parseChfArg i <*> traverse parseChfArg o
    sortedOperands m = sortOn fst <$> traverse (\(t, s) -> (,s) <$> parseOperand t) (M.toList m)
    writeScalar mem (op, s) = case op of
      OpBit {} -> case s of
        SBool b -> Right (writeOperand op (VBool b) mem)
        _ -> Left ("the bit operand " <> renderOperand op <> " takes true or false")
      _ -> (\w -> writeCell (operandCell op) w mem) <$> scalarToCellBits op s
    observe mem observed res =
      let (o1, o2, o3) = crOutputs res
          operands = M.fromList [(t, readScalar mem op) | (t, op) <- observed]
          vars = M.fromList [(name, valueScalar v) | name <- obsVars (rqObserve rq), Just v <- [lookupVar name]]
          -- exact spelling first, else any case (the names in upper case
          -- built once, the first of equal names kept)
          lookupVar name = case lookup name (crVars res) of
            Just v -> Just v
            Nothing -> M.lookup (T.map toUpper name) upperNames
          upperNames = M.fromListWith (\_ first -> first) [(T.map toUpper n, v) | (n, v) <- crVars res]
          err = fmap (\(RuntimeError c l (a, b, d)) -> ErrorReport (Just c) Nothing (Just l) (Just (a, b, d))) (crError res)
          ob = Observation operands vars (M.fromList [("OUTPUT1", o1), ("OUTPUT2", o2), ("OUTPUT3", o3)]) err
       in AnswerRun (maybe VerdictOk (const VerdictRuntimeError) err) ob


-- | An operand's value as the answer reports it: a bit as true/false, %F
-- and %TF as a binary32, the others as the signed reading of the pattern.
readScalar :: Memory -> Operand -> Scalar
readScalar mem op = case op of
  OpBit _ _ b -> SBool (testBit (readCell mem (operandCell op)) b)
  _
    | isReal -> scalarFromFloat (realFromBits w)
    | otherwise -> SNumber (fromInteger (signed (cellWidth (operandCell op)) (toInteger w)))
  where
    w = readCell mem (operandCell op)
    isReal = case op of
      OpSimple KF _ -> True
      OpTablePos TF _ _ -> True
      _ -> False
    signed width n = if n >= 2 ^ (width - 1) then n - 2 ^ width else n

valueScalar :: Value -> Scalar
valueScalar = \case
  VBool b -> SBool b
  VReal r -> scalarFromFloat r
  v -> maybe (SBool False) (SNumber . fromInteger) (valueToInteger v)

-- | The bit pattern a scalar writes into a (non-bit) operand: integers in
-- the signed or unsigned range of its width, REAL operands from a number.
scalarToCellBits :: Operand -> Scalar -> Either Text Word32
scalarToCellBits op s
  | isReal = case scalarToFloat s of
      Just f -> Right (realBits f)
      Nothing -> Left (renderOperand op <> " takes a REAL value")
  | otherwise = case s of
      SBits b | toInteger b < 2 ^ width -> Right b
      SNumber n | Just i <- smallInteger n, i >= negate (2 ^ (width - 1)), i < 2 ^ width ->
        Right (fromInteger (i `mod` (2 ^ width)))
      _ -> Left ("a value that does not fit the " <> T.pack (show width) <> " bits of " <> renderOperand op)
  where
    width = cellWidth (operandCell op) :: Int
    isReal = case op of
      OpSimple KF _ -> True
      OpTablePos TF _ _ -> True
      _ -> False
