-- | Running generated modules: directly on the syntax tree (check, then one
-- module call), or through the engine protocol (the printed source in a
-- @stref-engine/1@ request), and comparing two answers by what they
-- observe: the mapped operands, OUTPUT1..3 and the runtime error code.
module Stref.Explore.Run
  ( generatedSource
  , checkGenerated
  , runGenerated
  , Observed (..)
  , observeDirect
  , explorationRequest
  , Summary (..)
  , summarise
  , renderSummary
  , summaryDifference
  ) where

import Data.Bits (testBit)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import Stref.Check (checkModule)
import Stref.Checked (CModule, ModuleKind (..))
import Stref.Conformance.Protocol
import Stref.Diagnostics (RuntimeError (..))
import Stref.Engine (scalarToCellBits)
import Stref.Execution
import Stref.Generate.Program
import Stref.Operands
import Stref.Policy
import Stref.Syntax (noPos)
import Stref.Syntax.Pretty (prettyModule)
import Stref.Types (BasicType (..))
import Stref.Values
import Stref.Verification (VerificationError)

generatedSource :: GenModule -> Text
generatedSource = prettyModule . toModule

-- | Check the generated tree itself (no printing, no parsing).
checkGenerated :: Policies -> GenModule -> Either [VerificationError] CModule
checkGenerated p gm = checkModule p ProcedureModule (noPos <$ toModule gm)

-- | The end state of one module call on the generated inputs.
runGenerated :: Policies -> GenModule -> Either [VerificationError] (PlcState, CallResult)
runGenerated p gm = do
  cm <- checkGenerated p gm
  pure (runCall p defaultPlcConfig cm defaultCallInput initialPlcState {psMemory = initialMemory gm})

-- | What a run shows: each observed operand's bit pattern (a bit: 0 or 1),
-- the output signals and the error code.
data Observed = Observed
  { obsPatterns :: [(Text, Word32)]
  , obsSignals :: (Bool, Bool, Bool)
  , obsErrorCode :: Maybe Int
  }
  deriving (Eq, Show)

observeDirect :: GenModule -> (PlcState, CallResult) -> Observed
observeDirect gm (st, res) =
  Observed
    [(renderOperand o, pattern o) | o <- observedOperands gm]
    (crOutputs res)
    (reCode <$> crError res)
  where
    pattern o = case o of
      OpBit _ _ b -> if testBit (readCell (psMemory st) (operandCell o)) b then 1 else 0
      _ -> readCell (psMemory st) (operandCell o)

-- | A protocol request for the generated module under the given policies
-- (sent in full, so that an engine's own overrides decide what differs),
-- for the given number of module calls.
explorationRequest :: Policies -> Int -> Text -> GenModule -> Request
explorationRequest pol calls caseId gm =
  Request
    { rqProtocol = protocolVersion
    , rqCase = caseId
    , rqDialect = "mastertool-xe"
    , rqPolicies = M.fromList (policyAssignments pol)
    , rqSource = generatedSource gm
    , rqModule = "P"
    , rqPlc =
        PlcRequest
          { prDeclare = declareFromConfig defaultPlcConfig
          , prDiagnostics = renderOperand (OpSimple KM (plcDiagnostics defaultPlcConfig))
          , prInit = M.fromList [(renderOperand o, scalar v) | (o, v) <- gmInputs gm]
          , prChf = Nothing
          }
    , rqCalls = replicate (max 1 calls) (CallRequest (True, True, True) M.empty Nothing)
    , rqObserve = Observe (map renderOperand (observedOperands gm)) [] ["OUTPUT1", "OUTPUT2", "OUTPUT3"] True
    , rqProgram = Nothing
    , rqCycle = Nothing
    }
  where
    scalar = \case
      VBool b -> SBool b
      VReal r -> SBits (realBits r)
      v -> SNumber (maybe 0 fromInteger (valueToInteger v))

-- | An answer reduced to what the comparison looks at.
data Summary
  = SumRejected Text
  | SumUnsupported Text
  | SumEngineError Text
  | SumRun
      { sumOperands :: [(Text, Either Text Word32)] -- ^ patterns; 'Left' an unreadable value
      , sumOutputs :: [(Text, Maybe Bool)]
      , sumError :: Maybe Int
      , sumErrorLine :: Maybe Int -- ^ shown, not compared
      }
  deriving (Show)

instance Eq Summary where
  SumRejected _ == SumRejected _ = True
  SumUnsupported _ == SumUnsupported _ = True
  SumEngineError _ == SumEngineError _ = True
  SumRun o u e _ == SumRun o' u' e' _ = o == o' && u == u' && e == e'
  _ == _ = False

summarise :: GenModule -> Either Text Answer -> Summary
summarise gm = \case
  Left e -> SumEngineError e
  Right (AnswerRejected l _ msg) -> SumRejected (maybe "" (\n -> "line " <> tshow n <> ": ") l <> msg)
  Right (AnswerUnsupported r) -> SumUnsupported r
  Right (AnswerRun _ ob) ->
    SumRun
      [(renderOperand o, pattern o (M.lookup (renderOperand o) (obOperands ob))) | o <- observedOperands gm]
      [(k, M.lookup k (obOutputs ob)) | k <- ["OUTPUT1", "OUTPUT2", "OUTPUT3"]]
      (obError ob >>= erCode)
      (obError ob >>= erLine)
  where
    pattern o = \case
      Nothing -> Left "missing"
      Just s -> case o of
        OpBit {} -> case s of
          SBool b -> Right (if b then 1 else 0)
          _ -> Left "not a boolean"
        _ -> either Left Right (scalarToCellBits o s)

-- | One line per observation, in the notation of the corpus.
renderSummary :: GenModule -> Summary -> [Text]
renderSummary gm = \case
  SumRejected m -> ["rejected: " <> m]
  SumUnsupported m -> ["unsupported: " <> m]
  SumEngineError m -> ["engine error: " <> m]
  SumRun ops outs err line ->
    ["error: " <> maybe "none" (\c -> tshow c <> maybe "" (\l -> " at line " <> tshow l) line) err]
      ++ [o <> " = " <> either id (showPattern o) p | (o, p) <- ops]
      ++ [k <> " = " <> maybe "?" (\b -> if b then "true" else "false") v | (k, v) <- outs]
  where
    types = M.fromList ([(renderOperand (mvOperand v), mvType v) | v <- gmMapped gm] ++ [(renderOperand o, gaType a) | a <- gmArrays gm, o <- arrayOperands a])
    showPattern o w = case M.lookup o types of
      Just t
        | t == BOOL -> if w == 0 then "false" else "true"
        | otherwise -> showValue (patternValue t w)
      Nothing -> tshow w
    patternValue t w = readOperand (writeCell (CellSimple KI 0) w emptyMemory) (OpSimple KI 0) t

-- | The first observation on which two summaries differ, for messages.
summaryDifference :: Summary -> Summary -> Maybe Text
summaryDifference a b
  | a == b = Nothing
  | otherwise = case (a, b) of
      (SumRun o u e _, SumRun o' u' e' _)
        | e /= e' -> Just ("error " <> tshow e <> " vs " <> tshow e')
        | ((k, x, y) : _) <- [(k, x, y) | ((k, x), (_, y)) <- zip o o', x /= y] -> Just (k <> ": " <> pat x <> " vs " <> pat y)
        | otherwise -> Just ("outputs " <> tshow u <> " vs " <> tshow u')
      _ -> Just "different verdicts"
  where
    pat = either id (\w -> "pattern " <> tshow w)

tshow :: Show a => a -> Text
tshow = T.pack . show
