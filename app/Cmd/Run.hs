-- | @stref run FILE@: verify an ST module and run it for a number of module
-- calls on a simulated controller; print the operands that changed,
-- OUTPUT1..3 and the diagnostic band.
module Cmd.Run (command, PlcFile (..), readPlcFile) where

import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString as BS
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy.Char8 as BL
import Control.Exception (evaluate)
import Control.Monad (unless)
import Data.Char (isDigit)
import Data.Containers.ListUtils (nubOrd)
import Data.Foldable (forM_, toList)
import qualified Data.Map.Strict as M
import Data.Scientific (floatingOrInteger, toRealFloat)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import qualified Data.Yaml as Y
import Options.Applicative hiding (command)
import qualified Options.Applicative as O
import System.Exit
import System.IO (stderr, stdout)
import Cmd.Common
import Cmd.Iec (RunIecOptions (..), compareIec, defaultCycle, dialectPolicies, isIecDialect, runIec)
import Stref.Conformance.Case (Case (..), CallSetup (CallSetup), ExpValue (..), IecCall (..), IecSetup (..), iecScalar, parseScenario)
import Stref.IEC.Engine (Call (..), Evaluator (..))
import Stref.IEC.Eval (resetEvents)
import Stref.Policy (PolicyInfo (..), Policies, alternativesOf, lookupPolicy, setPolicy)
import Stref.Checked (CModule (..), ModuleKind (..))
import Stref.Diagnostics
import Stref.Execution
import Stref.Operands
import Stref.Run
import Stref.Trace (items, renderJsonLines, renderText, watching)
import Stref.Types (BasicType (INT))
import Stref.Values

data Options = Options
  { optFile :: FilePath
  , optCalls :: Int
  , optModule :: String
  , optPlc :: Maybe FilePath
  , optSets :: [String]
  , optInputs :: (Maybe String, Maybe String, Maybe String)
  , optChfIn :: [String]
  , optChfOut :: [String]
  , optPolicies :: [String]
  , optFormat :: String
  , optDialect :: String
  , optCycle :: Maybe String
  , optProgram :: Maybe String
  , optPresets :: [String]
  , optCompare :: Maybe String
  , optTrace :: TraceFlags
  , optScenario :: Maybe FilePath
  , optReadable :: Bool
  }

command :: Mod CommandFields (IO ExitCode)
command =
  O.command "run" $
    info
      (run <$> options)
      ( progDesc "Verify an ST module and run it for N module calls; print the operands that changed, OUTPUT1..3 and the diagnostic band. Exit 0, 1 for a rejected module or a runtime error, 2 for a usage error"
      )

options :: Parser Options
options =
  Options
    <$> strArgument (metavar "FILE" <> help "The ST module")
    <*> option callCount (long "calls" <> metavar "N" <> value 1 <> showDefault <> help ("Number of module calls (scan cycles), at most " <> show maxCalls))
    <*> strOption (long "module" <> metavar "P|F" <> value "P" <> showDefault <> help "Procedure module (CHP) or function module (CHF)")
    <*> optional (strOption (long "plc" <> metavar "PLC.yaml" <> help "The controller: declare, diagnostics, init, chf (as in a corpus case's plc key)"))
    <*> many (strOption (long "set" <> metavar "OPERAND=VALUE" <> help "Write an operand before the first call, e.g. %M0010=5, %M0006.6=TRUE, %F0002=2.5"))
    <*> ( (,,)
            <$> optional (strOption (long "input1" <> metavar "BOOL" <> help "INPUT1 on every call (default TRUE; FALSE: the module does not run)"))
            <*> optional (strOption (long "input2" <> metavar "BOOL" <> help "INPUT2 on every call (default TRUE)"))
            <*> optional (strOption (long "input3" <> metavar "BOOL" <> help "INPUT3 on every call (default TRUE)"))
        )
    <*> many (strOption (long "in" <> metavar "ARG" <> help "A CHF input parameter, in order (F modules): %M0010, %TM0010, %KM+5"))
    <*> many (strOption (long "out" <> metavar "ARG" <> help "A CHF output parameter, in order (F modules)"))
    <*> many (strOption (long "policy" <> metavar "K=V" <> help "Set a policy, e.g. overflow=wrap"))
    <*> strOption (long "format" <> metavar "text|json" <> value "text" <> showDefault <> help "Output format")
    <*> strOption (long "dialect" <> metavar "NAME" <> value "mastertool-xe" <> showDefault <> help "The dialect: mastertool-xe, tecomat or nexto (an IEC dialect: --set takes PATH=VALUE, e.g. MAIN.start=TRUE)")
    <*> optional (strOption (long "cycle" <> metavar "TIME" <> help "IEC dialects: the cycle (the virtual clock advances by it before each cycle); default: the greatest common divisor of the configuration's task intervals, else T#10ms"))
    <*> optional (strOption (long "program" <> metavar "NAME" <> help "IEC dialects: the PROGRAM to run (default: the configuration's, or the file's only one)"))
    <*> many (strOption (long "presets" <> metavar "NAME" <> help "IEC dialects: run under this preset too, side by side with the others given (repeatable: --presets tecomat --presets rusty); exit 1 when they differ"))
    <*> optional (strOption (long "compare" <> metavar "POLICY" <> help "IEC dialects: run under every alternative of this policy, side by side; exit 1 when they differ"))
    <*> traceFlags
    <*> optional (strOption (long "scenario" <> metavar "FILE" <> help "The calls as a YAML list, as a corpus case's calls: key (inputs and set per call; IEC: {set: ...}, a number of cycles, {reset: ...}); instead of --calls"))
    <*> switch (long "readable" <> help "IEC dialects: run every scan cycle in the readable evaluator, also where the fast one applies (same results, slower; docs/architecture.md)")

-- | What a PLC file describes.
data PlcFile = PlcFile
  { pfConfig :: PlcConfig
  , pfInit :: [(Operand, Setting)]
  , pfChfIn :: [ChfArg]
  , pfChfOut :: [ChfArg]
  }

run :: Options -> IO ExitCode
run o = case dialectPolicies (optDialect o) (optPolicies o) of
  Left msg -> usageError "run" msg
  Right pol | isIecDialect pol -> do
    srcE <- readSource (optFile o)
    case srcE of
      Left msg -> usageError "run" msg
      Right src -> case traverse splitSet (optSets o) of
        Left msg -> usageError "run" msg
        Right sets -> do
          scenario <- traverse (readScenario (optDialect o)) (optScenario o)
          case sequence scenario of
            Left msg -> usageError "run" msg
            Right calls -> do
              let ro = RunIecOptions (optCalls o) (maybe (defaultCycle pol (optFile o) src (T.pack <$> optProgram o)) T.pack (optCycle o)) (T.pack <$> optProgram o) sets (optFormat o == "json") (traceRequest (optTrace o)) (watchTable (optTrace o)) (iecScenario <$> calls) Nothing (if optReadable o then Readable else FastWhereItApplies)
              case variants pol of
                Left msg -> usageError "run" msg
                Right [] -> runIec pol (optFile o) src ro
                Right _ | traceRequest (optTrace o) /= Nothing || not (null (watchTable (optTrace o))) ->
                  usageError "run" "--compare and --presets show the variants side by side after the last cycle; --trace and --watch show one run (trace each variant with --policy K=V or --dialect)"
                Right vs -> compareIec vs (optFile o) src ro
  Right _
    | not (null (optPresets o)) -> usageError "run" "--presets compares the presets of the IEC dialects (--dialect tecomat, nexto or an engine's preset); the MasterTool XE controller has one preset: compare the alternatives of a policy with --compare POLICY"
    | otherwise -> runMasterTool o
  where
    -- the presets named (each with the --policy settings), or the dialect's
    -- preset under each alternative of the compared policy
    variants base = do
      fromPresets <- mapM (\n -> (T.pack n,) <$> dialectPolicies n (optPolicies o)) (optPresets o)
      mapM_ (\(n, p) -> if isIecDialect p then Right () else Left (n <> " is the MasterTool XE controller's preset, not an IEC dialect's")) fromPresets
      fromPolicy <- case optCompare o of
        Nothing -> Right []
        Just k -> case lookupPolicy (T.pack k) of
          Nothing -> Left ("no policy '" <> T.pack k <> "'; docs/policies.md lists them")
          Just info
            | null (piAlternatives info) -> Left ("the policy " <> T.pack k <> " takes a number, not one of several alternatives")
            | otherwise -> mapM (\a -> (T.pack k <> "=" <> a,) <$> setPolicy (T.pack k) a base) (piAlternatives info)
      if length (fromPresets ++ fromPolicy) == 1 then Left "give at least two presets to compare (--presets A --presets B)" else Right (fromPresets ++ fromPolicy)
    splitSet kv = case T.breakOn "=" (T.pack kv) of
      (k, v) | not (T.null v) -> Right (T.strip k, T.strip (T.drop 1 v))
      _ -> Left ("--set takes PATH=VALUE, e.g. MAIN.start=TRUE, not '" <> T.pack kv <> "'")

-- | A scenario file read as a case's calls under the dialect.
readScenario :: String -> FilePath -> IO (Either Text Case)
readScenario dialect file = do
  text <- readSource file
  pure (text >>= parseScenario file (T.pack dialect))

-- | An IEC scenario's cycles.
iecScenario :: Case -> [Call]
iecScenario c =
  [ maybe (Scan [(k, iecScalar v) | (k, v) <- icSet ic]) Reset (icReset ic >>= (`lookup` resetEvents))
  | ic <- maybe [] iecCalls (caseIec c)
  ]

runMasterTool :: Options -> IO ExitCode
runMasterTool o = do
  setup <- pure $ do
    pol <- applyPolicies (optPolicies o)
    kind <- case optModule o of
      "P" -> Right ProcedureModule
      "F" -> Right FunctionModule
      other -> Left ("--module takes P or F, not '" <> T.pack other <> "'")
    sets <- traverse parseSetArg (optSets o)
    ins <- traverse (parseChfArg . T.pack) (optChfIn o)
    outs <- traverse (parseChfArg . T.pack) (optChfOut o)
    inputs <- let (a, b, c) = optInputs o in (,,) <$> flag "input1" a <*> flag "input2" b <*> flag "input3" c
    fmtJson <- case optFormat o of
      "text" -> Right False
      "json" -> Right True
      other -> Left ("--format takes text or json, not '" <> T.pack other <> "'")
    if optCalls o < 0 || optCalls o > maxCalls then Left ("--calls takes a number from 0 to " <> T.pack (show maxCalls)) else Right ()
    pure (pol, kind, sets, ins, outs, inputs, fmtJson)
  case setup of
    Left msg -> usageError "run" msg
    Right (pol, kind, sets, ins, outs, inputs, fmtJson) -> do
      plcE <- maybe (pure (Right (PlcFile defaultPlcConfig [] [] []))) readPlcFile (optPlc o)
      srcE <- readSource (optFile o)
      scenarioE <- sequence <$> traverse (readScenario "mastertool-xe") (optScenario o)
      case (plcE, srcE, scenarioE) of
        (Left msg, _, _) -> usageError "run" msg
        (_, Left msg, _) -> usageError "run" msg
        (_, _, Left msg) -> usageError "run" msg
        (Right plc, Right src, Right scenario) -> do
          let chfIn = if null ins then pfChfIn plc else ins
              chfOut = if null outs then pfChfOut plc else outs
              runSetup = RunSetup pol (pfConfig plc) kind (pfInit plc ++ sets)
              callsOf = \case
                -- --input1..3 are the default of a scenario's calls that give none
                Nothing -> Right (replicate (optCalls o) (CallSpec inputs [] chfIn chfOut))
                Just c -> traverse (\(CallSetup given set) -> (\set' -> CallSpec given set' chfIn chfOut) <$> traverse setting set) (caseCalls c)
              setting (op, v) = case v of
                EInt n -> Right (op, SetInt n)
                EBool b -> Right (op, SetBool b)
                EReal f -> Right (op, SetReal f)
                EBits w -> Right (op, SetInt (toInteger w))
                _ -> Left ("the scenario sets " <> renderOperand op <> " to a value an operand cannot take")
              started = do
                calls <- either (Left . BadSetting) Right (callsOf scenario)
                cm <- compileSource pol kind (optFile o) src
                case [n | n <- watchTable (optTrace o), not (watchable cm n)] of
                  [] -> pure ()
                  bad : _ -> Left (BadSetting ("--watch " <> bad <> ": no variable or operand of that name (a variable as declared, P.X for a program's, or an operand such as %M0010)"))
                case traceRequest (optTrace o) of
                  Just (everyIteration, _) -> do
                    -- a traced run keeps its calls: a trace is read by a person
                    (outcome, events) <- runModuleTraced everyIteration runSetup cm calls
                    -- (the states between the calls are not kept: only a
                    -- watch table reads them, and a trace replaces it)
                    pure (roInitial outcome, foldr (\r rest -> CallStep r (roFinal outcome) rest) (CallsDone (roFinal outcome)) (roResults outcome), events, cmProgram cm)
                  Nothing -> (\(initial, stream) -> (initial, stream, [], cmProgram cm)) <$> streamModule runSetup cm calls
          case optCompare o of
            Just _ | traceRequest (optTrace o) /= Nothing || not (null (watchTable (optTrace o))) ->
              usageError "run" "--compare shows the alternatives side by side after the last call; --trace and --watch show one run (trace each alternative with --policy K=V)"
            Just name -> compareMasterTool fmtJson (optFile o) src (T.pack name) pol (\p -> RunSetup p (pfConfig plc) kind (pfInit plc ++ sets)) (callsOf scenario)
            Nothing -> case started of
                Left (BadSetting msg) -> usageError "run" msg
                Left (Rejected errs) | fmtJson -> BL.putStrLn (A.encode (rejectionJson (optFile o) errs)) >> pure (ExitFailure 1)
                Left (SyntaxError err) | fmtJson -> BL.putStrLn (A.encode (rejectionJson (optFile o) [err])) >> pure (ExitFailure 1)
                Left failure -> do
                  TIO.hPutStr stderr (renderRunFailure (optFile o) src failure)
                  pure (ExitFailure 1)
                Right (initial, stream, events, program) -> do
                  -- the trace first (text, or one JSON object per event), then
                  -- the usual report
                  forM_ (traceRequest (optTrace o)) $ \(_, watched) ->
                    mapM_ TIO.putStrLn $
                      (if fmtJson then renderJsonLines pol else renderText pol (sourceLine src)) (watching watched (items events))
                  -- the calls are printed as they happen, so that memory does
                  -- not grow with --calls
                  -- watched is known before the first call (lazy, the flags were
                  -- looked at again on every call: scan +0.4% instructions)
                  let !watched = watchTable (optTrace o)
                      !detail = parameterErrorDetail program (length chfIn) (length chfOut)
                      render k r st
                        | null watched = if fmtJson then printCallJson k r else printCallText detail k r
                        | otherwise = printCallWatch fmtJson watched k r st
                  if fmtJson then BL.putStr "{\"calls\":[" else pure ()
                  unless (null watched || fmtJson) $ TIO.putStrLn (watchRow (["call"] ++ watched ++ ["INTERNAL_OVERFLOW", "error"]))
                  ended <- consumeCalls render stream
                  case ended of
                    Left (BadSetting msg) -> usageError "run" msg
                    Left failure -> do
                      TIO.hPutStr stderr (renderRunFailure (optFile o) src failure)
                      pure (ExitFailure 1)
                    Right tally -> do
                      let summary = RunSummary (psMemory initial) (psMemory (tFinal tally)) (tLast tally)
                      if fmtJson
                        then BL.putStrLn ("]," <> BL.drop 1 (A.encode (jsonSummary (pfConfig plc) summary)))
                        else TIO.putStr (textSummary (pfConfig plc) summary)
                      pure $ if tFailed tally then ExitFailure 1 else ExitSuccess
  where
    flag name = \case
      Nothing -> Right True
      Just t -> maybe (Left ("--" <> name <> " takes TRUE or FALSE")) Right (parseBool (T.pack t))

bandCells :: PlcConfig -> [Cell]
bandCells cfg = map operandCell (diagnosticBand cfg)

-- | What a run leaves once its calls are printed.
data Tally = Tally
  { tLast :: !(Maybe CallResult)
  , tFailed :: !Bool -- ^ some call ended in a runtime error
  , tFinal :: !PlcState
  }

-- | How a call is printed: bytes, which may wait to be written with those of
-- the next calls, or an action.
data CallOutput = Bytes BB.Builder | Direct (IO ())

-- | Print the calls as the stream produces them, in batches of bytes.
consumeCalls :: (Int -> CallResult -> PlcState -> CallOutput) -> CallStream -> IO (Either RunFailure Tally)
consumeCalls render = go 1 mempty Nothing False
  where
    go !k pending lastResult !failed = \case
      CallStep r st rest -> do
        pending' <- case render k r st of
          Bytes b
            | k `mod` batch /= 0 -> pure (pending <> b)
            | otherwise -> mempty <$ putBytes (pending <> b)
          Direct act -> mempty <$ (putBytes pending >> act)
        go (k + 1) pending' (Just r) (failed || crError r /= Nothing) rest
      CallsDone final -> putBytes pending >> pure (Right (Tally lastResult failed final))
      CallsFailed failure -> putBytes pending >> pure (Left failure)
    batch = 256

-- | The memory before the first call and after the last, and the last call.
data RunSummary = RunSummary
  { rsBefore :: Memory
  , rsAfter :: Memory
  , rsLastCall :: Maybe CallResult
  }

-- | A watch table's row for one call (@--watch NAME@): each name's value
-- after the call (a variable by its name, as declared or qualified, or an
-- operand; @-@ for a variable when the module did not run), INTERNAL_OVERFLOW,
-- and the runtime error if any; as JSON, one object in the calls array.
printCallWatch :: Bool -> [Text] -> Int -> CallResult -> PlcState -> CallOutput
printCallWatch json names k r st
  | json = Direct (BL.putStr ((if k > 1 then "," else "") <> A.encode (A.object ["call" A..= k, "vars" A..= A.object [K.fromText n A..= showValue v | (n, Just v) <- zip names values], "internal_overflow" A..= crOverflow r, "error" A..= fmap errorText (crError r)])))
  | otherwise = Direct (TIO.putStrLn (watchRow ([T.pack (show k)] ++ map (maybe "-" showValue) values ++ [showValue (VBool (crOverflow r)), maybe (if crExecuted r then "" else "not executed (INPUT1 FALSE)") errorText (crError r)])))
  where
    values = map (watchedValue r st) names
    errorText e = T.pack (show (reCode e)) <> " at line " <> T.pack (show (reLine e))

-- | A watched name's value after a call: an operand, or a variable named
-- as declared (any case) or qualified (P.X, P.V[3]).
watchedValue :: CallResult -> PlcState -> Text -> Maybe Value
watchedValue r st name = case parseOperand name of
  Right op -> Just (observeOperand (psMemory st) op)
  Left _ -> case [v | (n, v) <- crVars r, T.toUpper n == upper || ("." <> upper) `T.isSuffixOf` T.toUpper n] of
    v : _ -> Just v
    [] -> Nothing
  where
    upper = T.toUpper name

-- | Does a --watch name name an operand or one of the module's variables?
watchable :: CModule -> Text -> Bool
watchable cm name = case parseOperand name of
  Right _ -> True
  Left _ -> any matches (map fst (cmNamed cm))
  where
    base = T.toUpper (T.takeWhile (/= '[') name)
    matches n = let u = T.toUpper n in u == base || ("." <> base) `T.isSuffixOf` u

watchRow :: [Text] -> Text
watchRow = T.stripEnd . T.concat . map (\c -> T.justifyLeft (max 12 (T.length c + 2)) ' ' c)

-- | One call's line. The common lines are built as bytes (ASCII); an error's
-- message goes through the handle's text encoding, as the rest of the report.
printCallText :: (RuntimeError -> Maybe Text) -> Int -> CallResult -> CallOutput
printCallText detail k r
  | not (crExecuted r) = Bytes (prefix <> ascii "not executed (INPUT1 is FALSE)\n")
  | Just e <- crError r = Direct (putBytes prefix >> TIO.putStr (describeError e <> maybe "" (": " <>) (detail e)) >> putBytes (overflow <> steps <> ascii "\n"))
  | otherwise = Bytes (prefix <> ascii "ok" <> overflow <> steps <> ascii "\n")
  where
    prefix = ascii "call " <> BB.intDec k <> ascii ": "
    -- MT-OP-7: said on every call that leaves the flag set
    overflow = if crOverflow r then ascii ", INTERNAL_OVERFLOW set" else mempty
    steps = ascii " (" <> BB.intDec (crSteps r) <> ascii " steps)"

-- | Bytes of a literal, packed once (a 'BB.Builder' literal would encode
-- its characters again on every line).
ascii :: BS.ByteString -> BB.Builder
ascii = BB.byteString

putBytes :: BB.Builder -> IO ()
putBytes = BB.hPutBuilder stdout

textSummary :: PlcConfig -> RunSummary -> Text
textSummary cfg summary =
  T.unlines $
    ["operands changed:"]
      ++ (if null changed then ["  (none)"] else ["  " <> T.justifyLeft 14 ' ' (renderOperand (cellOperand c)) <> cellText after c | (c, _, _) <- changed])
      ++ [ "outputs: " <> T.unwords ["OUTPUT" <> tshow i <> "=" <> showValue (VBool b) | (i, b) <- zip [1 :: Int ..] (outputsList lastOutputs)]
         , "diagnostics " <> renderOperand (OpSimple KM (plcDiagnostics cfg)) <> "..: " <> T.unwords [tshow (signedM after c) | c <- bandCells cfg]
         ]
  where
    after = rsAfter summary
    changed = [ch | ch@(c, _, _) <- changedCells cfg (rsBefore summary) after, c `notElem` bandCells cfg]
    lastOutputs = maybe (False, False, False) crOutputs (rsLastCall summary)

signedM :: Memory -> Cell -> Integer
signedM mem c = maybe 0 id (valueToInteger (readOperand mem (cellOperand c) INT))

-- | One element of the JSON report's "calls" array, with the comma before
-- every element but the first.
printCallJson :: Int -> CallResult -> CallOutput
printCallJson k r = Bytes ((if k > 1 then "," else "") <> element)
  where
    -- a call without an error, written directly: aeson's encoding of
    -- callJson, keys in sorted order
    element = case crError r of
      Nothing ->
        "{\"error\":null,\"executed\":" <> bool (crExecuted r) <> ",\"internal_overflow\":" <> bool (crOverflow r)
          <> ",\"outputs\":" <> outputs (crOutputs r) <> ",\"steps\":" <> BB.intDec (crSteps r) <> "}"
      Just _ -> BB.lazyByteString (A.encode callJson)
    bool b = if b then "true" else "false"
    outputs (a, b, c) = "{\"OUTPUT1\":" <> bool a <> ",\"OUTPUT2\":" <> bool b <> ",\"OUTPUT3\":" <> bool c <> "}"
    callJson =
      A.object
        [ "executed" A..= crExecuted r
        , "error" A..= (errorJson <$> crError r)
        , "outputs" A..= outputsJson (crOutputs r)
        , "steps" A..= crSteps r
        , "internal_overflow" A..= crOverflow r
        ]

-- | The JSON report without its "calls": the keys are encoded in sorted
-- order, so "calls" comes first and is printed before this object's keys.
jsonSummary :: PlcConfig -> RunSummary -> A.Value
jsonSummary cfg summary =
  A.object
    [ "operands" A..= A.object [K.fromText (renderOperand (cellOperand c)) A..= valueJson (observeOperand after (cellOperand c)) | (c, _, _) <- changed]
    , "outputs" A..= outputsJson (maybe (False, False, False) crOutputs (rsLastCall summary))
    , "diagnostics" A..= [signedM after c | c <- bandCells cfg]
    , "error" A..= (errorJson <$> (rsLastCall summary >>= crError))
    , "vars" A..= A.object [K.fromText n A..= valueJson v | (n, v) <- maybe [] crVars (rsLastCall summary)]
    ]
  where
    after = rsAfter summary
    changed = [ch | ch@(c, _, _) <- changedCells cfg (rsBefore summary) after, c `notElem` bandCells cfg]

errorJson :: RuntimeError -> A.Value
errorJson (RuntimeError code line (a, b, c)) = A.object ["code" A..= code, "line" A..= line, "comp" A..= [a, b, c]]

outputsJson :: (Bool, Bool, Bool) -> A.Value
outputsJson (a, b, c) = A.object ["OUTPUT1" A..= a, "OUTPUT2" A..= b, "OUTPUT3" A..= c]

outputsList :: (Bool, Bool, Bool) -> [Bool]
outputsList (a, b, c) = [a, b, c]

tshow :: Show a => a -> Text
tshow = T.pack . show

--------------------------------------------------------------------------------
-- PLC files

-- | Read a PLC description (YAML): @declare@, @diagnostics@, @init@, @chf@,
-- optionally under a top-level @plc@ key (so a corpus case's metadata
-- works). Declared kinds replace the project's default for that kind; kinds
-- not mentioned keep the default layout.
readPlcFile :: FilePath -> IO (Either Text PlcFile)
readPlcFile file = do
  missing <- notAFile file
  case missing of
    Just why -> pure (Left why)
    Nothing -> do
      r <- Y.decodeFileEither file
      pure $ case r of
        Left e -> Left (T.pack file <> ": " <> T.pack (Y.prettyPrintParseException e))
        Right v -> either (Left . ((T.pack file <> ": ") <>)) Right (plcFromJson v)

plcFromJson :: A.Value -> Either Text PlcFile
plcFromJson top = do
  o <- case top of
    A.Object o -> Right (maybe o id (KM.lookup "plc" o >>= asObject))
    A.Null -> Right KM.empty
    _ -> Left "expected a mapping with declare, diagnostics, init, chf"
  -- a misspelt key must not pass as an empty setting
  case [K.toText k | k <- KM.keys o, K.toText k `notElem` ["declare", "diagnostics", "init", "chf"]] of
    [] -> Right ()
    k : _ -> Left ("unknown key '" <> k <> "'; the keys are declare, diagnostics, init, chf")
  cfg0 <- maybe (Right defaultPlcConfig) (declare defaultPlcConfig) (KM.lookup "declare" o)
  cfg <- case KM.lookup "diagnostics" o of
    Nothing -> Right cfg0
    Just d -> (\a -> cfg0 {plcDiagnostics = a}) <$> diagnosticsAddress d
  inits <- maybe (Right []) settings (KM.lookup "init" o)
  (ins, outs) <- maybe (Right ([], [])) chf (KM.lookup "chf" o)
  pure (PlcFile cfg inits ins outs)
  where
    asObject = \case
      A.Object x -> Just x
      _ -> Nothing
    declare cfg = \case
      A.Object d -> foldl (\acc (k, v) -> acc >>= declareKind (K.toText k) v) (Right cfg) (KM.toList d)
      _ -> Left "declare: expected a mapping such as {M: 2000, TM: {10: 200}}"
    declareKind k v cfg = case (lookup k simpleKinds, lookup k tableKinds, v) of
      (Just sk, _, A.Number n) | Right i <- (floatingOrInteger n :: Either Double Int) -> Right cfg {plcSimple = M.insert sk i (plcSimple cfg)}
      (_, Just tk, A.Object ts) -> do
        tables <- traverse (\(a, n) -> (,) <$> intKey a <*> intValue n) (KM.toList ts)
        let others = M.filterWithKey (\(kind, _) _ -> kind /= tk) (plcTables cfg)
        Right cfg {plcTables = M.union others (M.fromList [((tk, a), n) | (a, n) <- tables])}
      _ -> Left ("declare: cannot read " <> k <> " (simple kinds take a count, tables a mapping address: positions)")
    simpleKinds = [(simpleLetter k, k) | k <- [minBound .. maxBound]]
    tableKinds = [(tableLetters k, k) | k <- [minBound .. maxBound]]
    intKey a = let t = K.toText a in if not (T.null t) && T.all isDigit t then Right (read (T.unpack t)) else Left ("'" <> t <> "' is not a table address")
    intValue = \case
      A.Number n | Right i <- (floatingOrInteger n :: Either Double Int) -> Right i
      _ -> Left "a table takes a number of positions"
    diagnosticsAddress = \case
      A.Number n | Right i <- (floatingOrInteger n :: Either Double Int) -> Right i
      A.String s -> case parseOperand s of
        Right (OpSimple KM a) -> Right a
        _ -> Left ("diagnostics: '" <> s <> "' is not a %M operand")
      _ -> Left "diagnostics: expected %Mnnnn"
    settings = \case
      A.Object m -> traverse (\(k, v) -> (,) <$> parseOperand (K.toText k) <*> settingFromJson v) (KM.toList m)
      _ -> Left "init: expected a mapping from operands to values"
    chf = \case
      A.Object m -> (,) <$> argList (KM.lookup "in" m) <*> argList (KM.lookup "out" m)
      A.Null -> Right ([], [])
      _ -> Left "chf: expected {in: [...], out: [...]}"
    argList = \case
      Nothing -> Right []
      Just (A.Array xs) -> traverse (\case A.String s -> parseChfArg s; _ -> Left "chf: parameters are strings such as \"%M0010\"") (toList xs)
      Just _ -> Left "chf: expected a list"

settingFromJson :: A.Value -> Either Text Setting
settingFromJson = \case
  A.Bool b -> Right (SetBool b)
  A.Number n -> case floatingOrInteger n :: Either Double Integer of
    Right i -> Right (SetInt i)
    Left _ -> Right (SetReal (toRealFloat n))
  A.String s -> parseSetting s
  A.Object o | Just (A.String b) <- KM.lookup "bits" o, Just h <- T.stripPrefix "0x" (T.toLower b), [(w, "")] <- readHexW h -> Right (SetReal (realFromBits w))
  other -> Left ("not a value: " <> T.pack (show other))
  where
    readHexW h = [(fromInteger n, r) | (n, r) <- readHexI (T.unpack h)]
    readHexI s = case span (`elem` ("0123456789abcdef" :: String)) s of
      ("", _) -> []
      (ds, r) -> [(foldl (\acc d -> acc * 16 + toInteger (hexDigit d)) 0 ds, r)]
    hexDigit d = length (takeWhile (/= d) "0123456789abcdef")

-- | The calls are printed as they happen and need constant memory; their
-- number is bounded so that a mistyped count does not run for hours
-- (docs/robustness.md).
maxCalls :: Int
maxCalls = 1000000

-- | A call count, read as an unbounded integer so that a huge number is
-- refused instead of wrapping around.
callCount :: ReadM Int
callCount = eitherReader $ \s -> case reads s :: [(Integer, String)] of
  [(n, "")]
    | n >= 0 && n <= toInteger maxCalls -> Right (fromInteger n)
  _ -> Left ("--calls takes a number from 0 to " <> show maxCalls <> ", not " <> s)

-- | @run FILE --compare POLICY@ for a MasterTool XE module: its calls under
-- every alternative of the policy, in step; after the last call the
-- operands changed, the outputs, INTERNAL_OVERFLOW, the diagnostic band and
-- the variables side by side, with the first call after which the
-- alternatives part (their results or the controller's memory differ).
compareMasterTool :: Bool -> FilePath -> Text -> Text -> Policies -> (Policies -> RunSetup) -> Either Text [CallSpec] -> IO ExitCode
compareMasterTool json file src name pol setupFor callsE = case (alternativesOf name pol, callsE) of
  (Left msg, _) -> usageError "run" msg
  (_, Left msg) -> usageError "run" msg
  (Right _, Right []) -> usageError "run" "--compare runs at least one call (--calls N, N >= 1)"
  (Right alts, Right calls) -> do
    let started = [(alt, p, compileSource p (rsKind (setupFor p)) file src >>= \cm -> streamModule (setupFor p) cm calls) | (alt, p) <- alts]
    case [f | (_, _, Left f) <- started] of
      failure : _ | length [() | (_, _, Right _) <- started] == 0 || isBadSetting failure -> case failure of
        Rejected errs | json -> BL.putStrLn (A.encode (rejectionJson file errs)) >> pure (ExitFailure 1)
        SyntaxError err | json -> BL.putStrLn (A.encode (rejectionJson file [err])) >> pure (ExitFailure 1)
        _ -> do
          TIO.hPutStr stderr (renderRunFailure file src failure)
          pure (ExitFailure (if isBadSetting failure then 2 else 1))
      _ -> do
        let cfg = rsPlc (setupFor pol)
            names = [name <> "=" <> alt | (alt, _, _) <- started]
            count = length calls
            -- the states before the first call, taken out now: nothing may
            -- hold the head of a stream while the calls run
            initials = [either (const Nothing) (Just . fst) s | (_, _, s) <- started]
            streams = [either (const Nothing) (Just . snd) s | (_, _, s) <- started]
        _ <- evaluate (count + length names)
        mapM_ (evaluate . maybe () (`seq` ())) initials
        case inStep 1 Nothing (map (const Nothing) streams) Nothing streams of
          Left failure -> TIO.hPutStr stderr (renderRunFailure file src failure) >> pure (ExitFailure 2)
          Right (parting, firstErrors, lastCalls, finals) -> do
            let changed = nubOrd [c | (Just i, Just f) <- zip initials finals, (c, _, _) <- changedCells cfg (psMemory i) (psMemory f), c `notElem` bandCells cfg]
                column f = maybe "rejected" f
                operandRows = [(renderOperand (cellOperand c), [column (\st -> cellText (psMemory st) c) st | st <- finals]) | c <- changed]
                callRows =
                  [("OUTPUT" <> tshow i, [column (\r -> showValue (VBool (outputsList (crOutputs r) !! (i - 1)))) r | r <- lastCalls]) | i <- [1 .. 3 :: Int]]
                    ++ [("INTERNAL_OVERFLOW", [column (showValue . VBool . crOverflow) r | r <- lastCalls])]
                    ++ [("diagnostics " <> renderOperand (OpSimple KM (plcDiagnostics cfg)) <> "..", [column (\st -> T.unwords [tshow (signedM (psMemory st) c) | c <- bandCells cfg]) st | st <- finals])]
                vars = nubOrd [n | Just r <- lastCalls, (n, _) <- crVars r]
                varRows = [(n, [column (\r -> maybe "-" showValue (lookup n (crVars r))) r | r <- lastCalls]) | n <- vars]
                errorText initial e = case (initial, e) of
                  (Nothing, _) -> "rejected"
                  (_, Nothing) -> "none"
                  (_, Just (k, err)) -> describeError err <> " in call " <> tshow k
            printComparison json $
              Comparison names "call" count parting (zipWith errorText initials firstErrors) (operandRows ++ callRows ++ varRows)
  where
    isBadSetting = \case
      BadSetting _ -> True
      _ -> False
    -- the streams in step: the first call after which they differ, each
    -- one's first error, last call and final state (Nothing: rejected)
    inStep :: Int -> Maybe Int -> [Maybe (Int, RuntimeError)] -> Maybe [Maybe CallResult] -> [Maybe CallStream] -> Either RunFailure (Maybe Int, [Maybe (Int, RuntimeError)], [Maybe CallResult], [Maybe PlcState])
    inStep !k !parting errs lastCalls streams = case sequence [maybe (Right Nothing) (fmap Just . step) s | s <- streams] of
      Left failure -> Left failure
      Right steps
        | all (maybe True isDone) steps -> Right (parting, errs, maybe (map (const Nothing) streams) id lastCalls, [s >>= finalState | s <- steps])
        | otherwise ->
            let nodes = [s >>= running | s <- steps]
                seen = [(\(r, st, _) -> (crOutputs r, crError r, crOverflow r, crVars r, psMemory st)) <$> n | n <- nodes]
                parting' = case parting of
                  Nothing | any (/= head seen) seen -> Just k
                  _ -> parting
                errs' = [maybe (nodes' >>= \(r, _, _) -> (k,) <$> crError r) Just e | (e, nodes') <- zip errs nodes]
                lasts = [(\(r, _, _) -> r) <$> n | n <- nodes]
                -- everything kept for the next call is evaluated now, so
                -- that no call's state is held until the end (10^6 calls)
                settled = forceEach errs' `seq` forceEach lasts
                forceEach :: [Maybe a] -> ()
                forceEach = foldr (\x acc -> maybe () (`seq` ()) x `seq` acc) ()
             in parting' `seq` settled `seq` inStep (k + 1) parting' errs' (Just lasts) [(\(_, _, rest) -> rest) <$> n | n <- nodes]
    step = \case
      CallsFailed failure -> Left failure
      s -> Right s
    isDone = \case
      CallsDone _ -> True
      _ -> False
    finalState = \case
      CallsDone st -> Just st
      _ -> Nothing
    running = \case
      CallStep r st rest -> Just (r, st, rest)
      _ -> Nothing
