-- | Running conformance cases against an engine and judging the answers.
--
-- An engine is the in-process reference ('referenceEngine') or an external
-- command, started once per case through @/bin/sh -c@ in a process group of
-- its own: the request goes to its standard input, the answer is read from
-- its standard output, at most 'roMaxAnswerBytes' bytes, within
-- 'roTimeout' seconds. Whatever else happens (non-zero exit, a signal, no
-- answer in time, too much output, invalid JSON) is an @engine-error@ for
-- that case; the whole group is killed and the run goes on. A persistent
-- engine ('roPersistent') answers many requests in one process, one a line
-- (Stref.Conformance.Persistent); it is restarted after such a case.
module Stref.Conformance.Runner
  ( EngineSpec (..)
  , RunOptions (..)
  , defaultRunOptions
  , Outcome (..)
  , Difference (..)
  , differenceText
  , CaseResult (..)
  , Exchange (..)
  , runCorpus
  , runCorpusUnlessEngineMissing
  , engineCannotStart
  , runOne
  , buildRequest
  , judge
  , judgeWith
  , varComparison
  , casePolicies
  , askEngine
  , runExternal
  , globMatch
  , inShard
  , unmatchedSelections
  ) where

import Control.Concurrent (forkIO)
import Control.Concurrent.Async (async, cancel, wait, waitCatch)
import Control.Exception (SomeAsyncException, SomeException, bracket, evaluate, fromException, throwIO, try)
import Control.Monad (void)
import qualified Data.ByteString as BS
import qualified Data.ByteString.Lazy as BL
import Data.Char (toUpper)
import Data.List.NonEmpty (NonEmpty)
import qualified Data.List.NonEmpty as NE
import Data.Maybe (fromMaybe, mapMaybe)
import qualified Data.Map.Strict as M
import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Encoding.Error as TE
import GHC.Clock (getMonotonicTime)
import System.Exit (ExitCode (..))
import System.IO (Handle, hClose)
import System.Process
import System.Timeout (timeout)
import Stref.Checked (ModuleKind (..))
import Stref.Conformance.Case
import Stref.Conformance.Corpus
import Stref.Conformance.Parallel (inParallel)
import Stref.Conformance.Persistent (Pool, askPersistent, cannotStart, closePool, exitedWith, newPool)
import Stref.Conformance.Protocol
import Stref.Engine (referenceEngine)
import Stref.Operands
import Stref.IEC.Engine (observedTypes, scalarsMatch)
import Stref.Policy (Policies, lookupPreset, mastertoolXE, policyAssignments, setPolicy)
import Stref.Values (realBits)

data EngineSpec
  = Reference [(Text, Text)] -- ^ the in-process reference, with policy overrides
  | External String -- ^ a shell command line
  deriving (Eq, Show)

data RunOptions = RunOptions
  { roEngine :: EngineSpec
  , roPolicies :: Policies -- ^ the engine's declared policies for MasterTool XE cases: choose @expect-if@, sent in requests
  , roOverrides :: Maybe [(Text, Text)]
  -- ^ 'Just': every case runs under its dialect's preset with these
  -- assignments (the default); 'Nothing': every case under 'roPolicies'
  , roJobs :: Int
  , roShard :: Maybe (Int, Int) -- ^ @(i, n)@, 1 <= i <= n
  , roFilters :: [Text] -- ^ globs on case ids; a case runs when it matches one (or none are given)
  , roFeatures :: [Text]
  , roLacking :: [Text] -- ^ features the engine declares it lacks: their cases are unsupported, the engine is not asked
  , roExcludeGiven :: [Text] -- ^ those of them given by --exclude-feature, which must each match a case (a features file may name others)
  , roRules :: [Text]
  , roTimeout :: Double -- ^ seconds per case
  , roKnownFailures :: S.Set Text
  , roMaxAnswerBytes :: Int
  , roPersistent :: Bool -- ^ the external engine answers many requests in one process, one a line
  , roPool :: Maybe Pool -- ^ its processes, during a run ('withEngines')
  }

defaultRunOptions :: RunOptions
defaultRunOptions =
  RunOptions
    { roEngine = Reference []
    , roPolicies = mastertoolXE
    , roOverrides = Just []
    , roJobs = 1
    , roShard = Nothing
    , roFilters = []
    , roFeatures = []
    , roLacking = []
    , roExcludeGiven = []
    , roRules = []
    , roTimeout = 10
    , roKnownFailures = S.empty
    , roMaxAnswerBytes = 16 * 1024 * 1024
    , roPersistent = False
    , roPool = Nothing
    }

-- | A difference between expectation and answer.
data Difference = Difference
  { dWhat :: Text -- ^ @%M0012@, @verdict@, @error.code@, @OUTPUT1@, @P.X@
  , dExpected :: Text
  , dActual :: Text
  }
  deriving (Eq, Show)

data Outcome
  = Pass
  | Fail (NonEmpty Difference) -- ^ every difference, in the order verdict, error, operands, variables, outputs
  | InvalidCase Text -- ^ the case file itself is malformed (counted as failed)
  | Unsupported Text
  | EngineError Text
  | Skipped Text -- ^ filtered out, or a known failure (with what went wrong)
  deriving (Eq, Show)

data CaseResult = CaseResult
  { resId :: Text
  , resFile :: FilePath
  , resCase :: Maybe Case
  , resOutcome :: Outcome
  , resKnownFailure :: Bool -- ^ listed in the known-failures file
  , resSeconds :: Double
  , resExchange :: Maybe Exchange -- ^ kept for a case an external engine failed
  }
  deriving (Eq, Show)

-- | What went to an external engine and what came back, as written.
data Exchange = Exchange
  { xcRequest :: Text
  , xcAnswer :: Maybe Text -- ^ 'Nothing': no answer was read (the engine failed, or took too long)
  }
  deriving (Eq, Show)

-- | Case @k@ (0-based, in id order) belongs to shard @k mod n + 1@.
inShard :: Maybe (Int, Int) -> Int -> Bool
inShard Nothing _ = True
inShard (Just (i, n)) k = k `mod` n == i - 1

-- | @*@ matches any run of characters (also @/@), @?@ one character.
globMatch :: Text -> Text -> Bool
globMatch pat = go (T.unpack pat) . T.unpack
  where
    go [] s = null s
    go ('*' : ps) s = any (go ps) (suffixes s)
    go ('?' : ps) (_ : s) = go ps s
    go (p : ps) (c : s) = p == c && go ps s
    go _ [] = False
    suffixes s = s : case s of
      [] -> []
      (_ : r) -> suffixes r

selected :: RunOptions -> Case -> Maybe Text
selected o c
  | not (null (roFilters o)) && not (any (`globMatch` caseId c) (roFilters o)) = Just "filtered out (--filter)"
  | not (null (roFeatures o)) && not (any (`elem` caseFeatures c) (roFeatures o)) = Just "filtered out (--feature)"
  | not (null (roRules o)) && not (any (`elem` caseRules c) (roRules o)) = Just "filtered out (--rule)"
  | otherwise = Nothing

-- | What in @--filter@, @--feature@ and @--rule@ selects no case of the
-- corpus, one message each: a misspelt selection must not pass as a run in
-- which every case was skipped. The whole corpus counts, not one shard,
-- since a shard may rightly hold no selected case.
unmatchedSelections :: RunOptions -> Corpus -> [Text]
unmatchedSelections o corpus
  | not (null unmatched) = unmatched
  | selecting && not (any chosen (corpusEntries corpus)) =
      ["the selection " <> T.unwords given <> " matches no case: each option matches some case, but no case matches all of them"]
  | otherwise = []
  where
    cases = [c | Loaded c <- corpusEntries corpus]
    ids = map entryId (corpusEntries corpus)
    features = S.fromList (concatMap caseFeatures cases)
    rules = S.fromList (concatMap caseRules cases)
    unmatched =
      ["--filter " <> g <> " matches no case id" | g <- roFilters o, not (any (globMatch g) ids)]
        ++ ["--feature " <> f <> " matches no case" | f <- roFeatures o, f `S.notMember` features]
        ++ ["--exclude-feature " <> f <> " matches no case" | f <- roExcludeGiven o, f `S.notMember` features]
        ++ ["--rule " <> r <> " matches no case" | r <- roRules o, r `S.notMember` rules]
    selecting = not (null (roFilters o) && null (roFeatures o) && null (roRules o))
    given = concat [["--" <> k, v] | (k, vs) <- [("filter", roFilters o), ("feature", roFeatures o), ("rule", roRules o)], v <- vs]
    -- a malformed case has no features or rules to select it by
    chosen = \case
      Loaded c -> selected o c == Nothing
      Invalid i _ _ -> null (roFeatures o) && null (roRules o) && any (`globMatch` i) (roFilters o)

-- | Run the corpus's entries (after sharding) and return one result each.
runCorpus :: RunOptions -> Corpus -> IO [CaseResult]
runCorpus o0 corpus = withEngines o0 $ \o -> runEntries o (shardEntries o corpus)

-- | Run with the processes of a persistent engine, ended afterwards.
withEngines :: RunOptions -> (RunOptions -> IO a) -> IO a
withEngines o act = case (roEngine o, roPersistent o, roPool o) of
  (External cmd, True, Nothing) -> bracket (newPool cmd) closePool (\pool -> act o {roPool = Just pool})
  _ -> act o

-- | How many cases must all show that an external engine cannot be started
-- before the run stops.
casesProbed :: Int
casesProbed = 3

-- | 'runCorpus', but an external engine that cannot be started at all stops
-- the run ('Left', with the error) instead of giving the same engine error
-- for every case. The cases run one by one until one shows the engine
-- working, or 'casesProbed' of them (or all, if fewer) show it missing;
-- the rest run as 'runCorpus' runs them.
runCorpusUnlessEngineMissing :: RunOptions -> Corpus -> IO (Either Text [CaseResult])
runCorpusUnlessEngineMissing o0 corpus = withEngines o0 (`unlessMissing` corpus)

unlessMissing :: RunOptions -> Corpus -> IO (Either Text [CaseResult])
unlessMissing o corpus = case roEngine o of
  Reference _ -> Right <$> runCorpus o corpus
  External _ -> probe [] [] (shardEntries o corpus)
  where
    -- results so far (reversed), the engine errors of the cases run so far
    probe done errors = \case
      []
        | not (null errors) -> pure (Left (missing errors))
        | otherwise -> pure (Right (finished done))
      e : rest -> do
        r <- runEntryAsIs o e
        case (runs o e, resOutcome r) of
          (False, _) -> probe (r : done) errors rest
          (True, EngineError err)
            | Just _ <- engineCannotStart (err : errors) ->
                if length errors + 1 >= casesProbed then pure (Left (missing (err : errors))) else probe (r : done) (err : errors) rest
          _ -> Right . (finished (r : done) ++) <$> runEntries o rest
    finished = map markKnown . reverse
    missing errors =
      "the engine cannot be started: " <> (if length errors == 1 then "the only case run" else "the first " <> T.pack (show (length errors)) <> " cases")
        <> " ended with: " <> fromMaybe "" (engineCannotStart errors)

-- | Do these engine errors, one per case, show an engine that cannot be
-- started at all? Yes when the shell could not run the command (status 127,
-- not found; 126, not executable) or the process could not be created, or
-- when all are one same error that says a file is missing. The error to
-- show is the answer.
engineCannotStart :: [Text] -> Maybe Text
engineCannotStart errors = case errors of
  first : _
    | all unstartable errors -> Just first
    | all (== first) errors, any (`T.isInfixOf` T.toLower first) missingWords -> Just first
  _ -> Nothing
  where
    unstartable e = any (`T.isPrefixOf` e) [exitedWith 127, exitedWith 126, cannotStart]
    missingWords = ["not found", "no such file", "cannot open", "can't open", "cannot find", "permission denied"]

shardEntries :: RunOptions -> Corpus -> [Entry]
shardEntries o corpus = [e | (k, e) <- zip [0 ..] (corpusEntries corpus), inShard (roShard o) k]

runEntries :: RunOptions -> [Entry] -> IO [CaseResult]
runEntries o entries
  | roJobs o <= 1 = mapM run1 entries
  | otherwise = inParallel (roJobs o) run1 entries
  where
    run1 e = markKnown <$> runEntryAsIs o e

-- | Is the entry run against the engine (not malformed, not filtered out)?
runs :: RunOptions -> Entry -> Bool
runs o = \case
  Loaded c -> selected o c == Nothing && null (lacking o c)
  Invalid {} -> False

-- | The features of a case that the engine declared it lacks.
lacking :: RunOptions -> Case -> [Text]
lacking o c = [f | f <- caseFeatures c, f `elem` roLacking o]

-- | Run one entry; a known failure is not yet marked ('markKnown').
runEntryAsIs :: RunOptions -> Entry -> IO CaseResult
runEntryAsIs o = \case
  Invalid i f msg -> pure (CaseResult i f Nothing (InvalidCase msg) (known o i) 0 Nothing)
  Loaded c -> case selected o c of
    Just why -> pure (CaseResult (caseId c) (caseFile c) (Just c) (Skipped why) (known o (caseId c)) 0 Nothing)
    Nothing
      | fs@(_ : _) <- lacking o c ->
          pure (CaseResult (caseId c) (caseFile c) (Just c) (Unsupported ("the engine lacks " <> T.intercalate ", " fs <> " (--exclude-feature, --features-file); it was not asked")) (known o (caseId c)) 0 Nothing)
    Nothing -> do
      t0 <- getMonotonicTime
      -- whatever goes wrong while running one case ends only that case
      -- the outcome decided here, in the worker (not later, by the report)
      (outcome, exchange) <- either (\e -> (EngineError ("the runner failed on this case: " <> T.pack (show e)), Nothing)) id <$> trySync (runCase o c >>= \(r, x) -> (,x) <$> evaluate r)
      t1 <- getMonotonicTime
      pure (CaseResult (caseId c) (caseFile c) (Just c) outcome (known o (caseId c)) (t1 - t0) exchange)

known :: RunOptions -> Text -> Bool
known o i = i `S.member` roKnownFailures o

-- | A known failure's failure or engine error is reported as skipped, with
-- what went wrong.
markKnown :: CaseResult -> CaseResult
markKnown r
  | resKnownFailure r = r {resOutcome = knownFailure (resOutcome r)}
  | otherwise = r
  where
    knownFailure = \case
      Fail ds -> Skipped ("known failure: " <> T.intercalate "; " (map differenceText (NE.toList ds)))
      EngineError e -> Skipped ("known failure: engine-error: " <> e)
      InvalidCase e -> InvalidCase e
      other -> other

-- | Catch what the action throws, but let cancellation and interrupts
-- (asynchronous exceptions) through.
trySync :: IO a -> IO (Either SomeException a)
trySync act = try act >>= \case
  Left e | Just (_ :: SomeAsyncException) <- fromException e -> throwIO e
  r -> pure r

-- | Run one case: build the request, ask the engine, judge the answer.
runOne :: RunOptions -> Case -> IO Outcome
runOne o c = fst <$> runCase o c

-- | 'runOne', keeping the exchange with an external engine when the case
-- failed or the engine misbehaved (only then: the request holds the whole
-- source).
runCase :: RunOptions -> Case -> IO (Outcome, Maybe Exchange)
runCase o c = case casePolicies o c of
  Left e -> pure (InvalidCase e, Nothing)
  Right pol -> do
    let ex = effectiveExpect pol c
        rq = buildRequest pol c ex
    (answer, written) <- converse o rq
    let outcome = case answer of
          Left e -> EngineError e
          Right a -> judgeWith (varComparison pol c ex) ex a
        exchange = case (roEngine o, outcome) of
          (External _, Fail _) -> Just (Exchange (requestText rq) written)
          (External _, EngineError _) -> Just (Exchange (requestText rq) written)
          _ -> Nothing
    pure (outcome, exchange)
  where
    requestText = TE.decodeUtf8 . BL.toStrict . encodeRequest

-- | The policies a case runs under: its dialect's preset with the run's
-- assignments, or the run's one record.
casePolicies :: RunOptions -> Case -> Either Text Policies
casePolicies o c = case roOverrides o of
  Nothing -> Right (roPolicies o)
  Just assignments -> do
    preset <- maybe (Left ("the dialect " <> caseDialect c <> " has no preset")) Right (lookupPreset (caseDialect c))
    foldl (\acc (k, v) -> acc >>= setPolicy k v) (Right preset) assignments

-- | How a named variable's expected value is compared with the answer: for
-- the IEC dialects under the variable's type (from the reference's check
-- of the case), for MasterTool XE as numbers.
varComparison :: Policies -> Case -> Expect -> Text -> ExpValue -> Scalar -> Bool
varComparison pol c ex = case caseIec c of
  Nothing -> \_ v s -> varMatches v s
  Just setup ->
    let types = observedTypes pol (caseSource c) (iecProgram setup) (M.keys (exVars ex))
     in \name v s -> case M.lookup name types of
          Just t -> scalarsMatch pol t (iecScalar v) s
          Nothing -> False

-- | The request for a case, observing exactly what the expectation names.
buildRequest :: Policies -> Case -> Expect -> Request
buildRequest pol c ex = case caseIec c of
  Just setup -> iecRequest pol c ex setup
  Nothing -> mastertoolRequest pol c ex

-- | An IEC dialect's request (§4.4).
iecRequest :: Policies -> Case -> Expect -> IecSetup -> Request
iecRequest pol c ex setup =
  Request
    { rqProtocol = protocolVersion
    , rqCase = caseId c
    , rqDialect = caseDialect c
    , rqPolicies = M.fromList (policyAssignments pol)
    , rqSource = caseSource c
    , rqModule = "P"
    , rqPlc = PlcRequest (Declare M.empty M.empty) "" (M.fromList [(k, iecScalar v) | (k, v) <- iecInit setup]) Nothing
    , rqCalls = [CallRequest (True, True, True) (M.fromList [(k, iecScalar v) | (k, v) <- icSet c]) (icReset c) | c <- iecCalls setup]
    , rqObserve = Observe [k | k <- M.keys (exVars ex), "%" `T.isPrefixOf` k] [k | k <- M.keys (exVars ex), not ("%" `T.isPrefixOf` k)] [] True
    , rqProgram = iecProgram setup
    , rqCycle = Just (iecCycle setup)
    }

mastertoolRequest :: Policies -> Case -> Expect -> Request
mastertoolRequest pol c ex =
  Request
    { rqProtocol = protocolVersion
    , rqCase = caseId c
    , rqDialect = caseDialect c
    , rqPolicies = M.fromList (policyAssignments pol)
    , rqSource = caseSource c
    , rqModule = case caseModule c of
        ProcedureModule -> "P"
        FunctionModule -> "F"
    , rqPlc =
        PlcRequest
          { prDeclare = declareFromConfig cfg
          , prDiagnostics = renderOperand (OpSimple KM (plcDiagnostics cfg))
          , prInit = M.fromList [(renderOperand op, expValueScalar op v) | (op, v) <- psInit plc]
          , prChf = fmap (uncurry ChfRequest) (psChf plc)
          }
    , rqCalls = [CallRequest (csInputs k) (M.fromList [(renderOperand op, expValueScalar op v) | (op, v) <- csSet k]) Nothing | k <- caseCalls c]
    , rqObserve =
        Observe
          { obsOperands = map renderOperand (M.keys (exOperands ex))
          , obsVars = M.keys (exVars ex)
          , obsOutputs = ["OUTPUT" <> T.pack (show n) | n <- M.keys (exOutputs ex)]
          , obsError = True
          }
    , rqProgram = Nothing
    , rqCycle = Nothing
    }
  where
    plc = casePlc c
    cfg = psConfig plc

-- | Ask the engine; 'Left' is an engine error.
askEngine :: RunOptions -> Request -> IO (Either Text Answer)
askEngine o rq = fst <$> converse o rq

-- | 'askEngine', with the answer as an external engine wrote it.
converse :: RunOptions -> Request -> IO (Either Text Answer, Maybe Text)
converse o rq = case roEngine o of
  Reference overrides -> do
    let answer = referenceEngine overrides rq
    -- the timeout's own exception must not be caught as a failure: 'try'
    -- stays outside 'timeout'
    r <- trySync (timeout (micros (roTimeout o)) (evaluate (BL.length (encodeAnswer answer))))
    pure . (,Nothing) $ case r of
      Left (e :: SomeException) -> Left ("the reference engine failed: " <> T.pack (show e))
      Right Nothing -> Left ("no answer within " <> secondsText (roTimeout o) <> " (reference engine)")
      Right (Just _) -> Right answer
  External cmd -> do
    r <- case roPool o of
      Nothing -> runExternal cmd (roTimeout o) (roMaxAnswerBytes o) (encodeRequest rq)
      Just pool -> askPersistent pool (roTimeout o) (roMaxAnswerBytes o) (encodeRequest rq)
    let decoded = r >>= \bytes -> case decodeAnswer (BL.fromStrict bytes) of
          Left e -> Left ("the answer is not a valid stref-engine/1 answer: " <> T.pack e <> excerpt bytes)
          Right a -> Right a
    pure (decoded, either (const Nothing) (Just . TE.decodeUtf8With TE.lenientDecode) r)
  where
    excerpt b = " (answer began: " <> T.pack (show (BS.take 80 b)) <> ")"

micros :: Double -> Int
micros s = max 1 (round (s * 1000000))

secondsText :: Double -> Text
secondsText s = T.pack (show s) <> " s"

-- | Start the command in its own process group, feed it the request, read at
-- most @limit@ bytes of answer. 'Left' says what went wrong.
runExternal :: String -> Double -> Int -> BL.ByteString -> IO (Either Text BS.ByteString)
runExternal cmd seconds limit input = do
  started <- try (createProcess (shell cmd) {std_in = CreatePipe, std_out = CreatePipe, std_err = CreatePipe, create_group = True})
  case started of
    Left (e :: SomeException) -> pure (Left (cannotStart <> ": " <> T.pack (show e)))
    Right (Just hin, Just hout, Just herr, ph) -> do
      pid <- getPid ph
      let killGroup = case pid of
            Just p -> void (try (readProcessWithExitCode "/bin/sh" ["-c", "kill -9 -" ++ show p ++ " 2>/dev/null"] "") :: IO (Either SomeException (ExitCode, String, String)))
            Nothing -> pure ()
      -- The pipes of a child process are blocking file descriptors: a thread
      -- reading one cannot be interrupted, so every blocking step runs in
      -- its own thread and only the waiting here is bounded by the timeout.
      _ <- forkIO (void (try (BL.hPut hin input >> hClose hin) :: IO (Either SomeException ())))
      errReader <- async (drainKeeping herr 2000)
      conversation <- async $ do
        out <- readLimited hout limit
        case out of
          Nothing -> pure (Left ("the answer exceeds " <> T.pack (show limit) <> " bytes"))
          Just bytes -> do
            code <- waitForProcess ph
            errText <- wait errReader
            pure $ case code of
              ExitSuccess -> Right bytes
              ExitFailure n
                | n < 0 -> Left ("the engine was killed by signal " <> T.pack (show (negate n)) <> stderrNote errText)
                | otherwise -> Left (exitedWith n <> stderrNote errText)
      outcome <- timeout (micros seconds) (waitCatch conversation)
      -- kill whatever is left of the engine's group, then reap and close in
      -- the background (a read still blocked ends when the group is dead)
      killGroup
      _ <- forkIO $ do
        void (try (waitForProcess ph) :: IO (Either SomeException ExitCode))
        cancel conversation
        cancel errReader
        mapM_ closeQuietly [hin, hout, herr]
      pure $ case outcome of
        Nothing -> Left ("no answer within " <> secondsText seconds)
        Just (Left e) -> Left ("talking to the engine failed: " <> T.pack (show e))
        Just (Right r) -> r
    Right _ -> pure (Left (cannotStart <> ": no pipes"))
  where
    stderrNote t = if T.null (T.strip t) then "" else "; stderr: " <> T.strip t
    closeQuietly :: Handle -> IO ()
    closeQuietly h = void (try (hClose h) :: IO (Either SomeException ()))

-- | Read to end of file, or 'Nothing' as soon as more than @limit@ bytes came.
readLimited :: Handle -> Int -> IO (Maybe BS.ByteString)
readLimited h limit = go 0 []
  where
    go n acc = do
      chunk <- BS.hGetSome h 65536
      if BS.null chunk
        then pure (Just (BS.concat (reverse acc)))
        else
          let n' = n + BS.length chunk
           in if n' > limit then pure Nothing else go n' (chunk : acc)

-- | Read to end of file, keeping the first @keep@ bytes as text.
drainKeeping :: Handle -> Int -> IO Text
drainKeeping h keep = go 0 []
  where
    go n acc = do
      r <- try (BS.hGetSome h 65536) :: IO (Either SomeException BS.ByteString)
      case r of
        Right chunk | not (BS.null chunk) ->
          let room = max 0 (keep - n)
           in go (n + BS.length chunk) (if room > 0 then BS.take room chunk : acc else acc)
        _ -> pure (TE.decodeUtf8With TE.lenientDecode (BS.concat (reverse acc)))

-- * Judging

-- | Compare an answer with the expectation; every difference is reported.
judge :: Expect -> Answer -> Outcome
judge = judgeWith (\_ v s -> varMatches v s)

-- | 'judge' with a comparison of named variables.
judgeWith :: (Text -> ExpValue -> Scalar -> Bool) -> Expect -> Answer -> Outcome
judgeWith matchVar ex = \case
  AnswerUnsupported r -> Unsupported r
  AnswerRejected line kind msg -> failOn $ case expectedVerdict ex of
    ExpRejected ->
      let rj = fromMaybe (ExpReject Nothing Nothing) (exReject ex)
       in [Difference "reject.line" (showT l) (maybe "no line" showT line <> " (" <> msg <> ")") | Just l <- [rjLine rj], line /= Just l]
            ++ [Difference "reject.kind" k (k' <> " (" <> msg <> ")") | (Just k, Just k') <- [(rjKind rj, kind)], k /= k']
    -- a rejected program has no state to compare
    v -> [Difference "verdict" (verdictText v) ("rejected" <> maybe "" (\l -> " at line " <> showT l) line <> ": " <> msg)]
  AnswerRun verdict ob ->
    let expected = expectedVerdict ex
        actualV = case verdict of
          VerdictOk -> ExpOk
          VerdictRuntimeError -> ExpRuntimeError
        answered = M.fromList (mapMaybe (\(t, s) -> either (const Nothing) (\op -> Just (op, s)) (parseOperand t)) (M.toList (obOperands ob)))
     in failOn $
          [Difference "verdict" (verdictText expected) (verdictText actualV <> maybe "" (\e -> " (" <> errorText e <> ")") (obError ob)) | expected /= actualV]
            ++ maybe [] pure (compareError (exError ex) (obError ob))
            ++ mapMaybe (\(op, v) -> compareOperand op v (M.lookup op answered)) (M.toList (exOperands ex))
            ++ mapMaybe (\(name, v) -> compareVar name v (lookupName name (M.union (obVars ob) (obOperands ob)))) (M.toList (exVars ex))
            ++ mapMaybe (\(n, b) -> compareOutput n b (lookupName ("OUTPUT" <> showT n) (obOutputs ob))) (M.toList (exOutputs ex))
  where
    failOn = maybe Pass Fail . NE.nonEmpty
    showT :: Show a => a -> Text
    showT = T.pack . show
    verdictText = \case
      ExpOk -> "ok"
      ExpRejected -> "rejected"
      ExpRuntimeError -> "runtime-error"
    errorText (ErrorReport c k l comp) =
      "error " <> maybe "" showT c <> maybe "" id k <> maybe "" (\x -> " at line " <> showT x) l <> maybe "" (\(a, b, d) -> " comp [" <> T.intercalate ", " (map showT [a, b, d]) <> "]") comp
    lookupName :: Text -> M.Map Text a -> Maybe a
    lookupName n m = case M.lookup n m of
      Just x -> Just x
      Nothing -> lookup (T.map toUpper n) [(T.map toUpper k, x) | (k, x) <- M.toList m]
    -- one difference at most: the actual error is shown whole
    compareError expected actual = case (expected, actual) of
      (Nothing, _) -> Nothing
      (Just ErrNone, Nothing) -> Nothing
      (Just ErrNone, Just e) -> Just (Difference "error" "none" (errorText e))
      (Just (ErrCode c _ _), Nothing) -> Just (Difference "error" ("error " <> showT c) "none")
      (Just (ErrKind k _), Nothing) -> Just (Difference "error" ("error " <> k) "none")
      (Just (ErrKind k l), Just e@(ErrorReport _ k' l' _))
        | Just k /= k' -> Just (Difference "error.kind" k (errorText e))
        | Just x <- l, l' /= Just x -> Just (Difference "error.line" (showT x) (maybe "not reported" showT l'))
        | otherwise -> Nothing
      (Just (ErrCode c l comp), Just e@(ErrorReport c'' _ l' comp'))
        | Just c /= c'' -> Just (Difference "error.code" (showT c) (errorText e))
        | Just x <- l, l' /= Just x -> Just (Difference "error.line" (showT x) (maybe "not reported" showT l'))
        | Just x <- comp, comp' /= Just x -> Just (Difference "error.comp" (showT x) (maybe "not reported" showT comp'))
        | otherwise -> Nothing
    compareOutput n b = \case
      Nothing -> Just (Difference ("OUTPUT" <> showT n) (boolText b) "not reported")
      Just b' | b /= b' -> Just (Difference ("OUTPUT" <> showT n) (boolText b) (boolText b'))
      _ -> Nothing
    boolText b = if b then "true" else "false"
    compareOperand op v = \case
      Nothing -> Just (Difference (renderOperand op) (renderExpValue v) "not reported")
      Just s
        | operandMatches op v s -> Nothing
        | otherwise -> Just (Difference (renderOperand op) (renderExpValue v) (scalarText s))
    compareVar name v = \case
      Nothing -> Just (Difference name (renderExpValue v) "not reported")
      Just s
        | matchVar name v s -> Nothing
        | otherwise -> Just (Difference name (renderExpValue v) (scalarText s))

-- | @%M0012: expected 32767, got -32768@
differenceText :: Difference -> Text
differenceText d = dWhat d <> ": expected " <> dExpected d <> ", got " <> dActual d

scalarText :: Scalar -> Text
scalarText = \case
  SNumber n -> maybe (T.pack (show (scientificToFloat n))) (T.pack . show) (smallInteger n)
  SBool b -> if b then "true" else "false"
  SBits w -> renderExpValue (EBits w)
  SNaN -> "nan"
  SText t -> t
  SList xs -> "[" <> T.intercalate ", " (map scalarText xs) <> "]"
  SMap m -> "{" <> T.intercalate ", " [k <> ": " <> scalarText v | (k, v) <- M.toList m] <> "}"

-- | An operand is a bit pattern of its width: an expected integer matches
-- the pattern read as signed or as unsigned; REAL operands compare binary32
-- values (any NaN matches @nan@).
operandMatches :: Operand -> ExpValue -> Scalar -> Bool
operandMatches op v s = case op of
  OpBit {} -> case (v, s) of
    (EBool b, SBool b') -> b == b'
    _ -> False
  _
    | operandIsReal op -> case scalarToFloat s of
        Nothing -> False
        Just f -> realMatches v f
    | otherwise -> case (expectedPattern, actualPattern) of
        (Just a, Just b) -> a == b
        _ -> False
  where
    w = operandBits op
    modW n = n `mod` (2 ^ w)
    fits n = n >= negate (2 ^ (w - 1)) && n < 2 ^ w
    expectedPattern = case v of
      EInt n | fits n -> Just (modW n)
      EBits b -> Just (toInteger b)
      _ -> Nothing
    actualPattern = case s of
      SNumber n | Just i <- smallInteger n, fits i -> Just (modW i)
      SBits b | toInteger b < 2 ^ w -> Just (toInteger b)
      _ -> Nothing

realMatches :: ExpValue -> Float -> Bool
realMatches v f = case v of
  ENaN -> isNaN f
  EReal r -> realBits r == realBits f
  EInt n -> realBits (fromInteger n) == realBits f
  EBits b -> b == realBits f
  EDecimal d -> realBits (scientificToFloat d) == realBits f
  _ -> False

-- | Named variables: integers compare as numbers (bit strings read
-- unsigned, as the reference reports them), REAL by binary32.
varMatches :: ExpValue -> Scalar -> Bool
varMatches v s = case (v, s) of
  (EBool b, SBool b') -> b == b'
  (EInt n, SNumber x) -> x == fromInteger n
  (EInt n, SBits b) -> toInteger b == n `mod` (2 ^ (32 :: Int))
  (EBits b, SNumber x) -> case smallInteger x of
    Just i -> i `mod` (2 ^ (32 :: Int)) == toInteger b
    Nothing -> maybe False (\f -> realBits f == b) (scalarToFloat s)
  (EBits b, SBits b') -> b == b'
  (EReal _, _) -> maybe False (realMatches v) (scalarToFloat s)
  (ENaN, _) -> maybe False isNaN (scalarToFloat s)
  _ -> False

