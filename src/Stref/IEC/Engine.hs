-- | The IEC model behind the engine protocol (corpus-format §4): parse and
-- check a compilation unit, run its programs over scan cycles on the
-- virtual clock, observe variables by path. Pure.
module Stref.IEC.Engine
  ( iecEngine
  , iecTrace
  , runProgram
  , runProgramTraced
  , runProgramWatched
  , runProgramWith
  , Evaluator (..)
  , cycleFunction
  , setPath
  , Call (..)
  , RunResult (..)
  , parseVarPath
  , observedTypes
  , valueScalar
  , programScalar
  , locationOf
  , scalarValue
  , scalarsMatch
  , cycleMillis
  ) where

import Control.Monad (foldM)
import Data.Char (isDigit, isSpace)
import qualified Data.Map.Strict as M
import Data.Maybe (mapMaybe)
import Data.Scientific (Scientific, base10Exponent, floatingOrInteger, fromFloatDigits)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Conformance.Protocol
import Stref.IEC.Check (ProgramChoice (..), checkUnit, locationType)
import Stref.IEC.Checked
import Stref.IEC.Eval
import Stref.IEC.Fast (fastCycle, fastCycles)
import Stref.IEC.Memory (Layout, unionMember)
import Stref.IEC.Parser (parseUnit, parseUnitExpr)
import Stref.IEC.Syntax
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Stref.Trace (Event)
import Stref.Verification (VerificationError (..))

-- | What a run of cycles left: the checked program, the machine after the
-- last cycle that ran, the first runtime error with its cycle (1-based).
data RunResult = RunResult
  { rrProgram :: Program
  , rrMachine :: Machine
  , rrError :: Maybe (Int, Stop)
  , rrCycles :: Int -- ^ cycles that ran
  }

-- | The task interval in milliseconds from a TIME literal.
cycleMillis :: Policies -> Text -> Either Text Integer
cycleMillis pol t = case parseUnitExpr pol t of
  Right (ELit _ (LTime ns)) | ns > 0 -> Right (ns `div` 1000000)
  _ -> Left ("the cycle '" <> t <> "' is not a positive TIME literal such as T#10ms")

-- | What happens between two observations: a scan cycle after writing
-- variables, or a reset of the controller (docs/nexto.md).
data Call = Scan [(Text, Scalar)] | Reset ResetEvent
  deriving (Eq, Show)

-- | Run a source over cycles; each cycle first writes its variables (paths
-- and values), then runs the programs at clock (k-1) × cycle (§4.1). After a
-- runtime error, policy @after-error@ decides whether later cycles run.
runProgram :: Policies -> FilePath -> Text -> ProgramChoice -> Integer -> [(Text, Scalar)] -> [Call] -> Either VerificationError (Either Text RunResult)
runProgram = runProgramTraced Nothing

-- | 'runProgram', traced when given whether to keep every loop iteration
-- ('traceOf' the result's machine gives the events, docs/trace.md).
runProgramTraced :: Maybe Bool -> Policies -> FilePath -> Text -> ProgramChoice -> Integer -> [(Text, Scalar)] -> [Call] -> Either VerificationError (Either Text RunResult)
runProgramTraced traced pol file src choice cycle initial calls =
  fmap fst <$> runProgramWatched (Nothing :: Maybe (Program -> Machine -> ())) traced pol file src choice cycle initial calls

-- | 'runProgramTraced', with what the observer, if any, reads from the
-- program and the machine after each cycle (@stref run --watch@), by cycle
-- number.
runProgramWatched :: Maybe (Program -> Machine -> a) -> Maybe Bool -> Policies -> FilePath -> Text -> ProgramChoice -> Integer -> [(Text, Scalar)] -> [Call] -> Either VerificationError (Either Text (RunResult, [(Int, a)]))
runProgramWatched = runProgramWith FastWhereItApplies

-- | Which evaluator runs the scan cycles of an untraced run: the readable
-- one ("Stref.IEC.Eval", the definition), or the fast one
-- ("Stref.IEC.Fast") where the program lies in its slice, which gives the
-- same machines and errors (test/IEC/FastSpec.hs; docs/architecture.md).
-- A traced run is always the readable evaluator's.
data Evaluator = Readable | FastWhereItApplies
  deriving (Eq, Show)

-- | The scan cycle of a program under an evaluator: @runCycle@, or the
-- fast cycle where it applies.
cycleFunction :: Evaluator -> Policies -> Program -> Integer -> Machine -> (Machine, Maybe Stop)
cycleFunction ev pol prog = case ev of
  FastWhereItApplies | Just fast <- fastCycle pol prog -> fast
  _ -> runCycle pol prog

-- | 'runProgramWatched' with the evaluator of the scan cycles.
runProgramWith :: Evaluator -> Maybe (Program -> Machine -> a) -> Maybe Bool -> Policies -> FilePath -> Text -> ProgramChoice -> Integer -> [(Text, Scalar)] -> [Call] -> Either VerificationError (Either Text (RunResult, [(Int, a)]))
runProgramWith ev observer traced pol file src choice cycle initial calls = do
  unit <- parseUnit pol file src
  prog <- checkUnit pol choice unit
  -- translated once for the whole run
  let scan = cycleFunction (maybe ev (const Readable) traced) pol prog
      -- consecutive cycles that nothing observes or writes before them run
      -- on the fast evaluator's slots without a machine between them
      batches = case (ev, traced, observer) of
        (FastWhereItApplies, Nothing, Nothing) -> fastCycles pol prog
        _ -> Nothing
  pure $ do
    let (started, initError) = initialize pol prog Nothing (maybe id startTrace traced (initialMachine prog))
    m0 <- foldM (setPath pol prog) started initial
    -- solo: how many cycles still to run one at a time (after a batch that
    -- left the fast evaluator's slice, its cycles are run one by one)
    let done m k err seen = Right (RunResult prog m err (k - 1), reverse seen)
        -- the run's error is its first: a cycle's stop is kept only if none came before
        firstError k stop err = maybe err (\s -> Just (maybe (k, s) id err)) stop
        go _ m k err seen [] = done m k err seen
        go solo m k err seen (Reset ev : rest) =
          let (m1, stop) = restart pol prog ev m
           in go solo m1 k (firstError k stop err) seen rest
        go solo m k err seen (Scan sets : rest) = do
          m1 <- foldM (setPath pol prog) m sets
          let (plain, later) = plainScans rest
              clocks = [toInteger (k - 1 + i) * cycle | i <- [0 .. length plain]]
          case batches of
            Just cycles | solo <= 0 && not (null plain) -> case cycles clocks m1 of
              -- the batch ran cycles k .. k + ran - 1, the last one stopped if any did
              Just (m2, ran, stop) ->
                let last' = k + ran - 1
                    err' = firstError last' stop err
                 in case err' `seq` stop of
                      Just _ | pAfterError pol == StopController -> Right (RunResult prog m2 err' last', reverse seen)
                      _ -> go 0 m2 (last' + 1) err' seen (drop (ran - 1) plain ++ later)
              Nothing -> one (length clocks) m1 k err seen rest
            _ -> one solo m1 k err seen rest
        one solo m1 k err seen rest = do
          let (m2, stop) = scan (toInteger (k - 1) * cycle) (traceCycle k m1)
              err' = firstError k stop err
              -- nothing kept without an observer: a long run stays in constant memory
              seen' = maybe seen (\f -> (k, f prog m2) : seen) observer
          -- err' and seen' evaluated now: left as thunks, each would hold
          -- its cycle's machine until the end of the run
          case err' `seq` seen' `seq` stop of
            Just _ | pAfterError pol == StopController -> Right (RunResult prog m2 err' k, reverse seen')
            _ -> go (solo - 1) m2 (k + 1) err' seen' rest
    case initError of
      Just e -> Right (RunResult prog m0 (Just (1, e)) 0, [])
      Nothing -> go (0 :: Int) m0 1 Nothing [] calls

-- | The cycles at the head of the calls that write nothing before them, at
-- most a thousand (a batch of the fast evaluator's), and the calls after.
plainScans :: [Call] -> ([Call], [Call])
plainScans calls =
  let (plain, rest) = span (\case Scan [] -> True; _ -> False) calls
      (batch, over) = splitAt 999 plain
   in (batch, over ++ rest)

-- | Write a variable or a located variable before a cycle.
setPath :: Policies -> Program -> Machine -> (Text, Scalar) -> Either Text Machine
setPath pol prog m (path, s)
  | "%" `T.isPrefixOf` path = do
      loc <- locationOf pol path
      v <- scalarValue pol (locationType loc) s
      Right (writeLocatedVar loc (locationType loc) v m)
  | otherwise = do
      steps <- parseVarPath path
      (_, t) <- maybe (Left ("the path " <> path <> " names no variable of the program")) Right (readVariablePath prog m steps)
      ty <- maybe (Left ("the type of " <> path <> " is not known")) Right t
      v <- scalarValue pol ty s
      maybe (Left ("the path " <> path <> " cannot be written")) Right (writeVariablePath prog m steps v)

locationOf :: Policies -> Text -> Either Text Location
locationOf pol t = case parseUnitExpr pol t of
  Right (ELocated _ l) -> Right l
  _ -> Left ("'" <> t <> "' is not a direct address such as %IX0.1 or %QW2")

-- | @MAIN.fb.Q@, @MAIN.a[2,3]@, @G@ as steps (names upper-cased).
parseVarPath :: Text -> Either Text [Step]
parseVarPath t0 = go (T.strip t0)
  where
    bad = Left ("'" <> t0 <> "' is not a variable path such as MAIN.x, MAIN.fb.Q, MAIN.a[2,3] or G")
    go t
      | T.null t = Right []
      | otherwise =
          let (name, rest) = T.span (\c -> c == '_' || c `elem` ['a' .. 'z'] || c `elem` ['A' .. 'Z'] || isDigit c) t
           in if T.null name then bad else (StepField (upperName name) :) <$> after rest
    after r = case T.uncons r of
      Nothing -> Right []
      Just ('.', r') -> go r'
      Just ('[', r') -> case T.breakOn "]" r' of
        (inside, close) | not (T.null close) -> do
          is <- mapM number (T.splitOn "," inside)
          (StepIndex is :) <$> after (T.drop 1 close)
        _ -> bad
      _ -> bad
    number x = case reads (T.unpack (T.filter (not . isSpace) x)) of
      [(n, "")] -> Right n
      _ -> bad

-- | The types of observed paths, from the checked program (the runner
-- compares values under them: REAL as binary32, TIME by value, ...).
observedTypes :: Policies -> Text -> Maybe Text -> [Text] -> M.Map Text Type
observedTypes pol src program paths = case parseUnit pol "<case>" src >>= checkUnit pol (maybe ProgramsOfConfiguration ProgramNamed program) of
  Left _ -> M.empty
  Right prog ->
    let m = initialMachine prog
     in M.fromList (mapMaybe (\p -> (p,) <$> typeOf prog m p) paths)
  where
    typeOf prog m p
      | "%" `T.isPrefixOf` p = either (const Nothing) (Just . locationType) (locationOf pol p)
      | otherwise = either (const Nothing) Just (parseVarPath p) >>= readVariablePath prog m >>= snd

-- | Answer one request of an IEC dialect.
iecEngine :: Policies -> Request -> Answer
iecEngine pol rq = either AnswerUnsupported fst (iecAnswer Nothing pol rq)

-- | The answer to a request with the trace of its run (@stref conformance
-- --explain@); every loop iteration kept when given @True@.
iecTrace :: Bool -> Policies -> Request -> (Answer, [Event])
iecTrace every pol rq = either (\e -> (AnswerUnsupported e, [])) id (iecAnswer (Just every) pol rq)

iecAnswer :: Maybe Bool -> Policies -> Request -> Either Text (Answer, [Event])
iecAnswer traced pol rq = do
  -- TC-POU-15, TC-VAR-7: the IEC model keeps program, FB and global state
  -- from cycle to cycle; re-initialising every call is the MasterTool
  -- controller's (policy lifetime), which this model does not have
  if pLifetime pol == PerCall
    then Left ("lifetime=per-call belongs to the MasterTool controller; the IEC model keeps its state across cycles " <> citing pol ["TC-POU-15", "NX-POU-1", "NX-POU-16"])
    else Right ()
  cycle <- cycleMillis pol (maybe "T#10ms" id (rqCycle rq))
  let choice = maybe ProgramsOfConfiguration ProgramNamed (rqProgram rq)
      initial = M.toList (prInit (rqPlc rq))
  calls <- mapM callOf (rqCalls rq)
  case runProgramTraced traced pol (T.unpack (rqCase rq)) (rqSource rq) choice cycle initial calls of
    Left (VerificationError k (Pos l _) msg) -> Right (AnswerRejected (Just l) (Just k) msg, [])
    Right (Left e) -> Left e
    Right (Right r) ->
      let vars = M.fromList [(p, s) | p <- obsVars (rqObserve rq) ++ obsOperands (rqObserve rq), Just s <- [observe r p]]
          err = (\(_, StopFault (Pos l _) f) -> ErrorReport Nothing (Just (faultKind f)) (Just l) Nothing) <$> rrError r
          ob = Observation M.empty vars M.empty err
       in Right (AnswerRun (maybe VerdictOk (const VerdictRuntimeError) err) ob, traceOf (rrMachine r))
  where
    callOf c = case callReset c of
      Nothing -> Right (Scan (M.toList (callSet c)))
      Just r -> maybe (Left ("the reset '" <> r <> "' is none of warm, cold, origin, download")) (Right . Reset) (lookup r resetEvents)
    observe r p
      | "%" `T.isPrefixOf` p = case locationOf pol p of
          Right l -> Just (programScalar (rrProgram r) (readLocatedVar (rrProgram r) l (locationType l) (rrMachine r)))
          Left _ -> Nothing
      | otherwise = case parseVarPath p of
          Right steps -> programScalar (rrProgram r) . fst <$> readVariablePath (rrProgram r) (rrMachine r) steps
          Left _ -> Nothing

-- | A value of a program stref ran, as the protocol carries it (§4.2): a
-- union as its members, read from its bytes in the program's layout.
programScalar :: Program -> Value -> Scalar
programScalar prog = scalarIn (Just (layoutOf prog))

-- | A value read from another engine's output, which holds no union.
valueScalar :: Value -> Scalar
valueScalar = scalarIn Nothing

scalarIn :: Maybe Layout -> Value -> Scalar
scalarIn ly = \case
  VBool b -> SBool b
  VInt _ n -> SNumber (fromInteger n)
  VReal f
    | isNaN f -> SNaN
    | otherwise -> scalarFromFloat f
  VLReal d
    | isNaN d -> SNaN
    | isInfinite d -> SText (if d > 0 then "LREAL#1.0E309" else "LREAL#-1.0E309")
    | otherwise -> SNumber (fromFloatDigits d)
  VArray _ xs -> SList (map (scalarIn ly) (foldr (:) [] xs))
  VStruct fs -> SMap (M.map (scalarIn ly) fs)
  u@(VUnion fs _) | Just l <- ly -> SMap (M.fromList [(k, scalarIn ly x) | (k, _) <- fs, Just x <- [unionMember l k u]])
  VInstance _ fs -> SMap (M.map (scalarIn ly) (M.filterWithKey (\k _ -> not ("$" `T.isInfixOf` k)) fs))
  v -> SText (renderValue v)

-- | A protocol value as a value of the type (literals parsed as ST).
scalarValue :: Policies -> Type -> Scalar -> Either Text Value
scalarValue pol ty s = case (ty, s) of
  (TElem BOOL, SBool b) -> Right (VBool b)
  (TElem e, SNumber n) | isInt e -> case integral n of
    Just i | fitInt e i -> Right (VInt e i)
    -- a bit string is a pattern: -1 and 65535 both denote WORD 16#FFFF
    Just i | isBitString e, i < 0, i >= negate (2 ^ (intBits e - 1)) -> Right (VInt e (i + 2 ^ intBits e))
    _ -> Left (T.pack (show n) <> " is not a value of " <> elemName e)
  (TSubrange e _ _, SNumber n) | Just i <- integral n -> Right (VInt e i)
  (TNumEnum _ e _, SNumber n) | Just i <- integral n -> Right (VInt e i)
  -- NX-TYPE-78: an address is a DWORD
  (TPointer _, SNumber n) | Just i <- integral n, fitInt DWORD i -> Right (VInt DWORD i)
  (TElem REAL, SNumber n) -> Right (VReal (scientificToFloat n))
  (TElem LREAL, SNumber n) -> Right (VLReal (scientificToDouble n))
  (TElem REAL, SNaN) -> Right (VReal (0 / 0))
  (TElem LREAL, SNaN) -> Right (VLReal (0 / 0))
  (TElem REAL, SBits w) -> Right (VReal (realFromBitsLocal w))
  (TArray bs t, SList xs) -> VArray bs . foldr (\x acc -> x `seqCons` acc) mempty <$> mapM (scalarValue pol t) xs
  (TStruct _ fs, SMap m) -> VStruct . M.fromList <$> mapM (\(k, x) -> maybe (Left ("no field " <> k)) (\t -> (upperName k,) <$> scalarValue pol t x) (lookup (upperName k) [(upperName n, t) | (n, t) <- fs])) (M.toList m)
  (_, SText t) -> literalValue pol ty t
  _ -> Left ("the value does not fit the type " <> typeText ty)
  where
    integral n = case floatingOrInteger n :: Either Double Integer of
      Right i | base10Exponent n < 40 -> Just i
      _ -> Nothing
    seqCons x acc = pure x <> acc
    realFromBitsLocal w = realFromBitsF w

realFromBitsF :: (Integral a) => a -> Float
realFromBitsF w = case scalarToFloat (SBits (fromIntegral w)) of
  Just f -> f
  Nothing -> 0

scientificToDouble :: Scientific -> Double
scientificToDouble n
  | base10Exponent n > 400 = if n > 0 then 1 / 0 else -1 / 0
  | base10Exponent n < -400 = 0
  | otherwise = fromRational (toRational n)

-- | An ST literal of §4.2 as a value of the type.
literalValue :: Policies -> Type -> Text -> Either Text Value
literalValue pol ty t = case parseUnitExpr pol t of
  Left _ -> Left ("'" <> t <> "' is not an ST literal")
  Right e -> maybe (Left ("'" <> t <> "' is not a value of " <> typeText ty)) Right (fromExpr e)
  where
    fromExpr = \case
      ELit _ l -> fromLit l
      EUn _ UNeg (ELit _ (LInt n)) -> fromLit (LInt (negate n))
      EUn _ UNeg (ELit _ (LReal r x)) -> fromLit (LReal (negate r) x)
      EEnum _ _ v -> enumValue v
      EVar _ v -> enumValue v
      EField _ (EVar _ _) v -> enumValue v
      _ -> Nothing
    enumValue v = case ty of
      TEnum n vs -> VEnum n <$> lookupCI v vs
      TNumEnum _ e vs -> VInt e <$> lookup (upperName v) [(upperName k, x) | (k, x) <- vs]
      _ -> Nothing
    lookupCI v vs = case [x | x <- vs, upperName x == upperName v] of
      (x : _) -> Just x
      [] -> Nothing
    fromLit l = case (ty, l) of
      (TElem TIME, LTime ns) -> Just (VTime TIME (ns `quot` 1000000))
      (TElem LTIME, LTime ns) -> Just (VTime LTIME ns)
      (TElem DATE, LDate ns) -> Just (VDate (ns `div` 1000000))
      (TElem TOD, LTod ns) -> Just (VTod (ns `div` 1000000))
      (TElem DT, LDT ns) -> Just (VDT (ns `div` 1000000))
      (TString _ _, LString s) -> Just (VString s)
      (TString _ _, LWString s) -> Just (VString s)
      (_, LBits n) -> fromLit (LInt n)
      (TElem e, LInt n) | isInt e, fitInt e n -> Just (VInt e n)
      (TNumEnum _ e _, LInt n) | fitInt e n -> Just (VInt e n)
      (TElem REAL, LReal r _) -> Just (VReal (fromRational r))
      (TElem LREAL, LReal r _) -> Just (VLReal (fromRational r))
      (TElem REAL, LInt n) -> Just (VReal (fromInteger n))
      (TElem LREAL, LInt n) -> Just (VLReal (fromInteger n))
      (TElem BOOL, LBool b) -> Just (VBool b)
      (_, LTyped _ inner) -> fromLit inner
      _ -> Nothing

-- | Do an expected and an answered value denote the same value of the type?
-- REAL and LREAL compare by their binary32 and binary64 values (any NaN
-- matches NaN); times by value; enumerated values by name.
scalarsMatch :: Policies -> Type -> Scalar -> Scalar -> Bool
scalarsMatch pol ty a b = case (scalarValue pol ty a, scalarValue pol ty b) of
  (Right x, Right y) -> same x y
  _ -> False
  where
    same x y = case (x, y) of
      (VReal f, VReal g) -> (isNaN f && isNaN g) || (f == g && isNegativeZero f == isNegativeZero g)
      (VLReal f, VLReal g) -> (isNaN f && isNaN g) || (f == g && isNegativeZero f == isNegativeZero g)
      (VEnum _ v, VEnum _ w) -> upperName v == upperName w
      (VArray _ xs, VArray _ ys) -> length xs == length ys && and (zipWith same (foldr (:) [] xs) (foldr (:) [] ys))
      (VStruct m, VStruct n) -> M.keys m == M.keys n && and (M.elems (M.intersectionWith same m n))
      _ -> x == y
