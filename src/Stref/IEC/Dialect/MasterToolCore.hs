-- | The MasterTool XE controller on the IEC core: a first slice
-- (docs/architecture.md, "MasterTool XE on the IEC core").
--
-- 'coreAnswer' answers a MasterTool request with the IEC parser, checker and
-- definitional evaluator ('Stref.IEC.Eval.runCycle'), under the MasterTool
-- preset, and the controller's rules around a module call written here:
-- operands as located variables (Stref.IEC.Dialect.MasterTool), per-call
-- initialisation of everything not mapped (MT-MAP-1), initialisers of
-- mapped variables written at every call (MT-MAP-15), undeclared mapped
-- operands (MT-MAP-8, MT-MAP-10: 2000-2002), the CHF parameters of an F
-- module (MT-PARAM-3..7: 2003-2012), INPUT1 (MT-SIG-3), OUTPUT1
-- (MT-SIG-4, MT-SIG-5), INTERNAL_OVERFLOW (MT-OP-7), the diagnostic band
-- (MT-DIAG-2, MT-DIAG-4).
-- What the slice does not cover yet it declines with the reason.
--
-- 'compareOnCore' runs a request through today's MasterTool engine
-- ('Stref.Engine.referenceEngine') and through the core, and says whether
-- their observable results agree.
module Stref.IEC.Dialect.MasterToolCore
  ( coreAnswer
  , Comparison (..)
  , compareOnCore
  , widenObservation
  ) where

import Control.Monad (forM, unless, when)
import Data.List (nub, sortOn)
import qualified Data.Map.Strict as M
import Data.Maybe (isJust)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import Stref.Conformance.Protocol
import Stref.Engine (referenceEngine, scalarToCellBits)
import Stref.IEC.Check (ProgramChoice (..), checkUnit)
import Stref.IEC.Checked (PouDef (..), Program (..), VarInfo (..), key, lookupPou)
import Stref.IEC.Dialect.MasterTool (operandLocation, operandTypes)
import Stref.IEC.Eval (Machine (..), Stop (..), initialMachine, initialize, readLocatedVar, readVariablePath, runCycle, writeLocatedVar, writeVariablePath)
import Stref.IEC.Parser (parseUnit)
import Stref.IEC.Syntax (Decl (..), Location (..), Pou (..), PouKind (..), Section (..), TypeSpec (..), Unit (..), VarBlock (..), VarDecl (..))
import Stref.IEC.Types (Elem (..), Type (..), intRange)
import Stref.IEC.Values (Fault (..), Step (..), Value (..))
import Stref.Operands (Cell (..), ChfArg (..), ConstKind (..), Operand (..), PlcConfig (..), SimpleKind (..), TableKind (..), cellDeclared, operandCell, operandKindCode, parseChfArg, parseOperand, renderOperand)
import Stref.Policy (Policies (..), overflowFlagName)
import Stref.Syntax (Pos (..), noPos)
import Stref.Values (realFromBits)
import Stref.Verification (VerificationError (..))

-- | The unit and its checked program, or the core's rejection.
checkedOnCore :: Policies -> Request -> Either VerificationError (Unit, Program)
checkedOnCore pol rq = do
  u <- withSignals <$> parseUnit pol (T.unpack (rqCase rq)) (rqSource rq)
  -- the verifier reports the first error of the module: the checker's or
  -- one of the rules of the module's kind, whichever stands first
  case (checkUnit pol ProgramsOfConfiguration u, moduleKindRules (T.toUpper (rqModule rq) == "F") u) of
    (Right prog, Nothing) -> Right (u, prog)
    (Right _, Just k) -> Left k
    (Left e, Just k) | vePos k < vePos e -> Left k
    (Left e, _) -> Left e

-- | The rules of the module's kind, which is the configuration's and not
-- the source's: a procedure (P) module has no parameters (MT-PARAM-2,
-- MT-VERR-35); a function (F) module at most 10 inputs (VAR_INPUT and
-- VAR_IN_OUT) and 10 outputs (MT-PARAM-1, MT-VERR-33, MT-VERR-34).
moduleKindRules :: Bool -> Unit -> Maybe VerificationError
moduleKindRules isF (Unit decls) = case [p | DPou p <- decls, pouKind p == KProgram] of
  p : _
    | not isF, b : _ <- parameterBlocks p -> Just (VerificationError "procedure-parameters" (vbPos b) "a procedure (P) module takes no parameters; VAR_INPUT, VAR_IN_OUT and VAR_OUTPUT need a function (F) module (MT-VERR-35)")
    | isF, (n, _) : _ <- drop 10 (names [SecInput, SecInOut] p) -> Just (VerificationError "too-many-inputs" n "an F module has at most 10 VAR_INPUT and VAR_IN_OUT parameters together (MT-VERR-33)")
    | isF, (n, _) : _ <- drop 10 (names [SecOutput] p) -> Just (VerificationError "too-many-outputs" n "an F module has at most 10 VAR_OUTPUT parameters (MT-VERR-34)")
  _ -> Nothing
  where
    parameterBlocks p = [b | b <- pouVars p, vbSection b `elem` [SecInput, SecInOut, SecOutput]]
    names secs p = [n | b <- pouVars p, vbSection b `elem` secs, d <- vbDecls b, n <- vdNames d]

-- | MT-SIG-1: the module's signals INPUT1..3 and OUTPUT1..3, BOOL variables
-- the controller declares for every module.
signals :: [Text]
signals = ["INPUT1", "INPUT2", "INPUT3", "OUTPUT1", "OUTPUT2", "OUTPUT3"]

-- | The BOOL globals the controller declares: the signals, and the overflow
-- flag INTERNAL_OVERFLOW (MT-OP-7, MT-SIG-6), which the core's + - * unary -
-- and EXPT set under the preset's @overflow-flag@.
withSignals :: Unit -> Unit
withSignals (Unit decls) = Unit (DGlobals (VarBlock noPos SecGlobal False False [VarDecl noPos [(noPos, n)] Nothing (TSName noPos "BOOL") Nothing Nothing [] [] | n <- signals ++ [overflowFlagName]] False []) : decls)

-- | The mapped variables of the program (globals and the program's own),
-- each with its initial value when its declaration has an initialiser.
mapped :: Unit -> Program -> [(Location, Type, Maybe Value)]
mapped (Unit decls) prog =
  [(l, viType v, initial l v) | v <- prGlobals prog, Just l <- [viAt v]]
    ++ [(l, viType v, initial l v) | (_, t) <- prRoots prog, Just d <- [lookupPou prog t], v <- pdVars d, Just l <- [viAt v]]
  where
    initialised = [(n, l) | d <- concat [vbDecls b | b <- [b | DGlobals b <- decls] ++ concat [pouVars p | DPou p <- decls]], isJust (vdInit d), Just l <- [vdAt d], (_, n) <- vdNames d]
    initial l v = if (viName v, l) `elem` initialised then Just (viInit v) else Nothing

-- | The operands a mapped variable covers: its operand, or for an array
-- the row of as many operands from it on (MT-MAP-9: element k at the
-- first operand + k - lower bound), Nothing when one lies beyond the
-- addresses an operand can have.
coveredOperands :: Location -> Type -> Maybe [Operand]
coveredOperands l t = do
  op <- either (const Nothing) Just (parseOperand (locText l))
  let n = case t of
        TArray b _ -> product [hi - lo + 1 | (lo, hi) <- b]
        _ -> 1
  ops <- traverse (next op) [0 .. n - 1]
  ops <$ traverse (either (const Nothing) Just . parseOperand . renderOperand) ops
  where
    next op i = case op of
      OpSimple k a -> Just (OpSimple k (a + fromInteger i))
      OpTablePos k a p -> Just (OpTablePos k a (p + fromInteger i))
      OpBit {} | i == 0 -> Just op
      _ -> Nothing

-- | The mapped variables in declaration order, as the controller checks
-- their operands (MT-MAP-8): the globals, the variables of each function
-- (MT-MAP-14), then the PROGRAM's.
mappedInOrder :: Unit -> Program -> [(Location, Type)]
mappedInOrder (Unit decls) prog =
  [(l, viType v) | v <- prGlobals prog, Just l <- [viAt v]]
    ++ [(l, viType v) | DPou p <- decls, pouKind p == KFunction, Just d <- [lookupPou prog (pouName p)], v <- pdVars d, Just l <- [viAt v]]
    ++ [(l, viType v) | (_, t) <- prRoots prog, Just d <- [lookupPou prog t], v <- pdVars d, Just l <- [viAt v]]

-- | An operand's location (one 'coveredOperands' accepted).
placeOfOperand :: Operand -> Location
placeOfOperand op = either (const (Location "" ' ' ' ' [])) id (operandLocation op)

-- | MT-PARAM-3..7: the CHF arguments bound to the PROGRAM's VAR_INPUT (the
-- first ones), VAR_IN_OUT (the last ones; True marks a VAR_INPUT) and
-- VAR_OUTPUT, checked before the first statement: the
-- counts (2009, 2010), then each input and each output in order, a type of
-- Table 4-8 (2003, 2004), no bit of an operand, a table only for an array,
-- constants only for a VAR_INPUT that is no array (MT-PARAM-6), a constant
-- that fits (2008, MT-PARAM-7), every operand declared (2005, 2006), an
-- array within its table (2011, 2012). The error's first complement is the
-- parameter's number.
chfParameters :: PlcConfig -> [(VarInfo, Bool)] -> [VarInfo] -> [ChfArg] -> [ChfArg] -> Either (Int, (Int, Int, Int)) ([(VarInfo, Either Value Operand)], [(VarInfo, Operand)])
chfParameters cfg ins outs chfIns chfOuts
  | length chfIns /= length ins = Left (2009, (0, 0, 0)) -- MT-ERR-2009
  | length chfOuts /= length outs = Left (2010, (0, 0, 0)) -- MT-ERR-2010
  | otherwise = (,) <$> sequence (zipWith3 input [1 ..] ins chfIns) <*> sequence (zipWith3 output [1 ..] outs chfOuts)
  where
    param code n = Left (code, (n, 0, 0))
    input n (v, isInput) = \case
      ChfConstant kind r -> case viType v of
        -- MT-PARAM-6 (2), MT-PARAM-7
        TElem e | isInput, constantFits kind e -> maybe (param 2008 n) (Right . (v,) . Left) (constantValue e r)
        _ -> param 2003 n
      arg -> (v,) . Right <$> operandParam 2003 2005 2011 n v arg
    output n v = \case
      ChfConstant {} -> param 2004 n
      arg -> (v,) <$> operandParam 2004 2006 2012 n v arg
    takes op e = e `elem` operandTypes (placeOfOperand op)
    declared = cellDeclared cfg
    operandParam eType eDecl eShort n v arg = case (viType v, arg) of
      -- MT-PARAM-6 (3): no partial operands; (4): tables only to arrays
      (_, ChfOperand OpBit {}) -> param eType n
      (TElem e, ChfOperand op@OpSimple {})
        | not (takes op e) -> param eType n -- MT-PARAM-6 (1), Table 4-8
        | not (declared (operandCell op)) -> param eDecl n -- MT-PARAM-6 (6)
        | otherwise -> Right op
      -- MT-PARAM-6 (5), (7): an array takes a block of simple operands or
      -- (part of) a table, declared over its whole size
      (t@(TArray [_] (TElem e)), ChfOperand op@OpSimple {})
        | not (takes op e) -> param eType n
        | Just ops <- coveredOperands (placeOfOperand op) t, all (declared . operandCell) ops -> Right op
        | otherwise -> param eDecl n
      (TArray [(lo, hi)] (TElem e), ChfOperand op@(OpTablePos k a p)) -> table eType eDecl eShort n e (hi - lo + 1) k a p op
      (TArray [(lo, hi)] (TElem e), ChfTable k a) -> table eType eDecl eShort n e (hi - lo + 1) k a 0 (OpTablePos k a 0)
      _ -> param eType n
    table eType eDecl eShort n e len k a p op
      | not (takes op e) = param eType n
      | not (M.member (k, a) (plcTables cfg)) || not (declared (CellTable k a p)) = param eDecl n
      | not (declared (CellTable k a (p + fromInteger len - 1))) = param eShort n -- MT-ERR-2011, 2012
      | otherwise = Right op
    constantFits kind e = case kind of
      KFConst -> e == REAL
      _ -> e `elem` [USINT, BYTE, INT, WORD, DINT, DWORD]
    constantValue e r
      | e == REAL = if abs r <= toRational (3.4028235e38 :: Float) then Just (VReal (fromRational r)) else Nothing
      | otherwise =
          let (lo, hi) = intRange e
              i = truncate r
           in if fromInteger i == r && i >= lo && i <= hi then Just (VInt e i) else Nothing

-- | An operand as a location and the type of its whole width.
operandPlace :: Operand -> Either Text (Location, Type)
operandPlace op = (\l -> (l, TElem (widthType op))) <$> operandLocation op
  where
    widthType = \case
      OpBit {} -> BOOL
      OpSimple k _ -> case k of
        KM -> WORD
        KI -> DWORD
        KF -> DWORD
        _ -> BYTE
      OpTablePos TM _ _ -> WORD
      OpTablePos {} -> DWORD

-- | Write a scalar of the request into an operand.
writeScalar :: Machine -> (Operand, Scalar) -> Either Text Machine
writeScalar m (op, s) = do
  (l, t) <- operandPlace op
  case (op, s) of
    (OpBit {}, SBool b) -> Right (writeLocatedVar l t (VBool b) m)
    (OpBit {}, _) -> Left ("the bit operand " <> renderOperand op <> " takes true or false")
    _ -> (\w -> writeLocatedVar l t (VInt DWORD (toInteger w)) m) <$> scalarToCellBits op s

-- | An operand's value as the MasterTool engine reports it: a bit as
-- true/false, %F as a binary32, the others as the signed reading.
readScalar :: Program -> Machine -> Operand -> Either Text Scalar
readScalar prog m op = do
  (l, t) <- operandPlace op
  pure $ case (op, readLocatedVar prog l t m) of
    (OpBit {}, VBool b) -> SBool b
    (OpSimple KF _, VInt _ n) -> scalarFromFloat (realFromBits (fromInteger n :: Word32))
    (OpTablePos TF _ _, VInt _ n) -> scalarFromFloat (realFromBits (fromInteger n :: Word32))
    (OpSimple k _, VInt _ n) -> signed (if k == KM then 16 else if k == KI then 32 else 8) n
    (OpTablePos k _ _, VInt _ n) -> signed (if k == TM then 16 else 32) n
    (_, v) -> SBool (v == VBool True)
  where
    signed :: Int -> Integer -> Scalar
    signed w n = SNumber (fromInteger (if n >= 2 ^ (w - 1) then n - 2 ^ w else n))

-- | The MasterTool code of a runtime error of the core (corpus-format §4.3
-- kinds; MT-ERR-2015, MT-ERR-2020, MT-ERR-2030, MT-ERR-2050).
masterToolCode :: Text -> Maybe Int
masterToolCode = \case
  "index-out-of-range" -> Just 2015
  "division-by-zero" -> Just 2020
  "watchdog" -> Just 2030
  "call-depth" -> Just 2050 -- MT-ERR-2050, at the line of the call (A27)
  _ -> Nothing

-- | The core's answer to a MasterTool request, or why the slice declines it.
coreAnswer :: Policies -> Request -> Either Text Answer
coreAnswer pol rq = do
  let isF = T.toUpper (rqModule rq) == "F"
  unless (isF || T.toUpper (rqModule rq) == "P") (Left "a module neither P nor F")
  -- MT-PARAM-2: the arguments of a CHF call an F module
  (chfIns, chfOuts) <- case prChf plc of
    Nothing -> Right ([], [])
    Just c
      | isF -> (,) <$> traverse parseChfArg (chfIn c) <*> traverse parseChfArg (chfOut c)
      | otherwise -> Left "CHF parameters of a P module"
  unless (null (obsVars (rqObserve rq))) (Left "named variables observed")
  diag <- case parseOperand (prDiagnostics plc) of
    Right (OpSimple KM a) -> Right a
    _ -> Left "the diagnostic band is not at a %M operand"
  let cfg = declareToConfig diag (prDeclare plc)
  initial <- operandList (prInit plc)
  calls <- forM (rqCalls rq) $ \c -> do
    when (isJust (callReset c)) (Left "a reset of the controller")
    (,) (callInputs c) <$> operandList (callSet c)
  observed <- traverse (\t -> (t,) <$> parseOperand t) (obsOperands (rqObserve rq))
  when (null calls) (Left "no calls")
  case checkedOnCore pol rq of
    Left e -> Right (AnswerRejected (Just (posLine (vePos e))) (Just (veKind e)) (veMessage e))
    Right (unit, prog) -> do
      -- MT-MAP-8, MT-MAP-10: every operand a mapped variable covers (each
      -- element of an array), in declaration order: the first one the
      -- configuration does not declare is a runtime error before the first
      -- statement, at the line of decision A2
      cells <- maybe (Left "a mapped operand beyond the addresses of its kind") (Right . map operandCell . concat) (traverse (uncurry coveredOperands) (mappedInOrder unit prog))
      let undeclared = case filter (not . cellDeclared cfg) cells of
            [] -> Nothing
            c : _ -> Just (pErrorLineBeforeStart pol, undeclaredCell c)
          undeclaredCell c = case c of
            CellSimple _ a -> (2000, (operandKindCode c, a, 0)) -- MT-ERR-2000
            CellTable k a p
              | M.member (k, a) (plcTables cfg) -> (2002, (operandKindCode c, a, p)) -- MT-ERR-2002
              | otherwise -> (2001, (operandKindCode c, a, 0)) -- MT-ERR-2001
      (inst, pdef) <- case [(key i, d) | (i, t) <- prRoots prog, Just d <- [lookupPou prog t]] of
        [x] -> Right x
        _ -> Left "not one PROGRAM"
      let params sec = [v | v <- pdVars pdef, viSection v == sec]
      let parameters = chfParameters cfg ([(v, True) | v <- params SecInput] ++ [(v, False) | v <- params SecInOut]) (params SecOutput) chfIns chfOuts
          preStart = case (undeclared, parameters) of
            (Just e, _) -> Just e
            (_, Left e) -> Just (pErrorLineBeforeStart pol, e)
            _ -> Nothing
          (inputs, outputs) = either (const ([], [])) id parameters
          field v = [StepField inst, StepField (viKey v)]
      m0 <- foldlM writeScalar (initialMachine prog) {mMemory = M.empty} initial
      let band = [OpSimple KM (diag + i) | i <- [0 .. 4]]
          bandValues = \case
            Nothing -> [-32768, 0, 0, 0, 0] -- MT-DIAG-4
            Just (line, (code, (c1, c2, c3))) -> [line, code, c1, c2, c3] -- MT-DIAG-2
          writeBand m e = foldlM writeScalar m (zip band (map (SNumber . fromIntegral) (bandValues e)))
          call (m, _) ((input1, input2, input3), sets) = do
            m1 <- foldlM writeScalar m sets
            case preStart of
              _ | not input1 -> Right (m1, ((False, False, False), Nothing)) -- MT-SIG-3
              -- MT-MAP-8, MT-PARAM-6: the module stops before its data and signals are set
              Just e -> (,((False, False, False), Just e)) <$> writeBand m1 (Just e)
              Nothing -> do
                -- MT-MAP-1: a fresh data area at every call, over the operands;
                -- MT-MAP-15: initialisers of mapped variables write their operands
                let initialised = foldl (\acc (l, t, v) -> maybe acc (\x -> writeLocatedVar l t x acc) v) m1 (mapped unit prog)
                    (m2, initStop) = initialize pol prog Nothing (initialMachine prog) {mMemory = mMemory initialised}
                when (isJust initStop) (Left "an error while initialising")
                -- MT-PARAM-3: VAR_INPUT and VAR_IN_OUT from the CHF inputs, after
                -- the data area; a VAR_IN_OUT is a copy during the call (MT-PARAM-5)
                m2' <- foldlM (\acc (v, src) -> maybe (Left "a parameter the core cannot write") Right (writeVariablePath prog acc (field v) (either id (\op -> readLocatedVar prog (placeOfOperand op) (viType v) m2) src))) m2 inputs
                -- MT-SIG-4: the signals at the start of the call; A5, MT-OP-7 (d):
                -- INTERNAL_OVERFLOW FALSE
                let start = m2' {mGlobals = foldr (uncurry M.insert) (mGlobals m2') (zip (signals ++ [overflowFlagName]) (map VBool [input1, input2, input3, True, False, False, False]))}
                    (m3, stop) = runCycle pol prog 0 start
                    output k = M.lookup k (mGlobals m3) == Just (VBool True)
                err <- case stop of
                  Nothing -> Right Nothing
                  Just (StopFault p f) -> case masterToolCode (faultKind f) of
                    Just code -> Right (Just (posLine p, (code, (0, 0, 0))))
                    Nothing -> Left ("the runtime error " <> faultKind f <> ", which has no MasterTool code")
                -- MT-PARAM-5, MT-PARAM-3, A19: after a normal end the VAR_IN_OUT
                -- back to their operands, then VAR_OUTPUT to the CHF outputs (an
                -- output wins where both name one operand)
                let copyBack = [(v, op) | (v, Right op) <- inputs, viSection v == SecInOut] ++ outputs
                m3' <- if isJust err then Right m3 else foldlM (\acc (v, op) -> maybe (Left "a parameter the core cannot read") (\(x, _) -> Right (writeLocatedVar (placeOfOperand op) (viType v) x acc)) (readVariablePath prog m3 (field v))) m3 copyBack
                m4 <- writeBand m3' err
                -- MT-SIG-5: a runtime error clears OUTPUT1
                Right (m4, ((not (isJust err) && output "OUTPUT1", output "OUTPUT2", output "OUTPUT3"), err))
      (final, (outs, err)) <- foldlM call (m0, ((False, False, False), Nothing)) calls
      operands <- M.fromList <$> traverse (\(t, op) -> (t,) <$> readScalar prog final op) observed
      let (o1, o2, o3) = outs
          report = fmap (\(line, (code, comps)) -> ErrorReport (Just code) Nothing (Just line) (Just comps)) err
      Right (AnswerRun (maybe VerdictOk (const VerdictRuntimeError) err) (Observation operands M.empty (M.fromList [("OUTPUT1", o1), ("OUTPUT2", o2), ("OUTPUT3", o3)]) report))
  where
    plc = rqPlc rq
    operandList mp = sortOn fst <$> traverse (\(t, s) -> (,s) <$> parseOperand t) (M.toList mp)
    foldlM f z = foldl (\acc x -> acc >>= \a -> f a x) (Right z)

-- | The kinds with which the core's checker rejects a program for the rule
-- that MasterTool reports with the given kind (Table 5-1, MT-VERR): where
-- the core has one kind for several of MasterTool's messages (a syntax
-- error, a type that does not fit), a MasterTool kind names the rule more
-- closely, and two rejections at the same line agree when their kinds are
-- paired here. A kind absent here agrees only with itself.
coreKindsOf :: Text -> [Text]
coreKindsOf = \case
  -- MT-VERR-1, MT-VERR-2: a character or a spelling the lexer does not take
  -- (MT-LEX-2..16) is the core's syntax error, or its invalid identifier
  "invalid-char" -> ["expected-token", "invalid-identifier"]
  "invalid-symbol" -> ["expected-token", "invalid-identifier"]
  -- MT-VERR-5, MT-VERR-6: syntax errors; a reserved word where a name
  -- stands (MT-LEX-17) is the core's reserved-name
  "unexpected-after" -> ["expected-token"]
  "unexpected" -> ["expected-token", "reserved-name"]
  -- MT-VERR-4 for a second dimension, which MasterTool's grammar lacks
  -- (MT-ARR-5, MT-TYPE-3); the core checks the number of dimensions
  "expected-token" -> ["too-many-dimensions"]
  -- MT-VERR-9, MT-VERR-23: a name that is no variable (an undeclared array,
  -- a function's name outside its body)
  "undeclared-array" -> ["undeclared-variable"]
  "not-a-variable" -> ["undeclared-variable"]
  "not-a-function" -> ["undeclared-function"] -- MT-VERR-21
  -- MT-VERR-11, MT-VERR-12, MT-VERR-13, MT-VERR-22, MT-STMT-16: a value of
  -- a type the context does not take (a CASE selector, an assignment, an
  -- operand, an indexed name, a FOR bound)
  "integer-expression-expected" -> ["type-mismatch"]
  "impossible-conversion" -> ["type-mismatch"]
  "invalid-binary-operation" -> ["type-mismatch"]
  "not-an-array" -> ["type-mismatch"]
  "for-type-mismatch" -> ["type-mismatch"]
  _ -> []

-- | What a comparison finds.
data Comparison
  = Agree
  | Disagree Text -- ^ both answer, differently
  | Declined Text -- ^ outside the slice, with the reason
  deriving (Eq, Show)

-- | The request with every operand the program maps, the operands of the
-- CHF arguments and the diagnostic band added to what is observed, so that the comparison sees more than the
-- case's expectation lists.
widenObservation :: Policies -> Request -> Request
widenObservation pol rq = case checkedOnCore pol rq of
  Left _ -> rq
  Right (unit, prog) ->
    let chfOperands = [renderOperand op | Just c <- [prChf (rqPlc rq)], Right (ChfOperand op) <- map parseChfArg (chfIn c ++ chfOut c)]
        extra = [renderOperand op | (l, t, _) <- mapped unit prog, op <- concat (coveredOperands l t)] ++ chfOperands ++ either (const []) (\case OpSimple KM a -> [renderOperand (OpSimple KM (a + i)) | i <- [0 .. 4]]; _ -> []) (parseOperand (prDiagnostics (rqPlc rq)))
        ob = rqObserve rq
     in rq {rqObserve = ob {obsOperands = nub (obsOperands ob ++ extra)}}

-- | Run a MasterTool request through the MasterTool engine and the core.
compareOnCore :: Policies -> Request -> Comparison
compareOnCore pol rq0 =
  let rq = widenObservation pol rq0
   in case coreAnswer pol rq of
        Left why -> Declined why
        Right core -> judge (referenceEngine [] rq) core
  where
    judge ref core = case (ref, core) of
      (AnswerUnsupported w, _) -> Declined ("the MasterTool engine: " <> w)
      (AnswerRejected l k _, AnswerRejected l' k' _)
        | l == l' && (k == k' || maybe False (\(mk, ck) -> ck `elem` coreKindsOf mk) ((,) <$> k <*> k')) -> Agree
        | otherwise -> Declined ("both reject, MasterTool " <> shown (l, k) <> ", the core " <> shown (l', k'))
      (AnswerRejected _ k _, AnswerRun {}) -> Declined ("MasterTool rejects it (" <> maybe "?" id k <> "), a verification rule the core does not have yet")
      (AnswerRun {}, AnswerRejected _ k m) -> Declined ("the core rejects it (" <> maybe "?" id k <> "): " <> m)
      (AnswerRun v o, AnswerRun v' o')
        | v == v' && o == o' -> Agree
        | otherwise -> Disagree ("MasterTool " <> shown (v, o) <> "; the core " <> shown (v', o'))
      (_, AnswerUnsupported w) -> Declined w
    shown :: Show x => x -> Text
    shown = T.pack . show
