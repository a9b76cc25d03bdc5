-- | The IronPLC adapter (docs/engines.md): how a case of an IEC dialect
-- becomes a program IronPLC's @ironplcc@ compiles to bytecode, how
-- @ironplcvm@ runs it over the case's cycles, and how their output becomes
-- a stref-engine/1 answer.
--
-- Everything here is pure; "Stref.Engines.Run" runs the tools. The adapter
-- uses only what the installed tools offer, so it runs what they can show:
--
-- * @ironplcvm@ schedules its tasks on the wall clock: a program that
--   reads the clock (TON, TOF, TP, RTC, TIME()) gets no virtual clock, and
--   its case is @unsupported@.
-- * It has no way to write a variable between cycles, nor a direct
--   address before the first: such cases are @unsupported@.
-- * Its VM runs one program; a case with several is @unsupported@.
-- * @--dump-vars@ prints the globals and then the program's variables,
--   each as @NAME: VALUE@; strings, arrays, structures and the members of
--   FB instances do not come out readable, so a case that observes them
--   is @unsupported@.
--
-- The case is compiled before any of this is decided, so that what
-- IronPLC rejects is answered @rejected@ whether or not it could run.
module Stref.Engines.Ironplc
  ( Plan (..)
  , Run (..)
  , plan
  , caseFile
  , compileAnswer
  , RunOutcome (..)
  , runAnswer
  , dumpValue
  ) where

import Data.Char (isAlphaNum, isDigit, isSpace)
import Data.List (find)
import qualified Data.Map.Strict as M
import Data.Maybe (listToMaybe, mapMaybe)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Read as TR
import Stref.Conformance.Protocol
import Stref.IEC.Check (ProgramChoice (..), checkUnit)
import Stref.IEC.Checked
import Stref.IEC.Engine (parseVarPath, valueScalar)
import Stref.IEC.Parser (parseUnit)
import Stref.IEC.Syntax
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy (Extensions (..), Policies (..))
import Text.Read (readMaybe)

-- | What to compile, and how to run it if it compiles.
data Plan = Plan
  { planSource :: Text -- ^ the case's source, unchanged
  , planFlags :: [String] -- ^ ironplcc's options for the case's dialect
  , planRun :: Either Text Run -- ^ how to run it, or why the VM cannot
  }

data Run = Run
  { runScans :: Int -- ^ the case's cycles
  , runSeconds :: Int -- ^ how long the VM may take: its tasks keep the wall clock
  , runObserved :: [(Text, Text, Type)] -- ^ each observed path, its name in the dump, its type
  }

-- | The name of the file the adapter gives ironplcc.
caseFile :: Text
caseFile = "case.st"

-- | The plan for a request.
plan :: Policies -> Request -> Plan
plan pol rq = Plan (rqSource rq) (dialectFlags pol) $ case parseUnit pol "case.st" (rqSource rq) of
  -- a case stref rejects, which IronPLC compiled: run it, observing
  -- nothing, to answer what the engine made of it
  Left _ -> Right accepted
  Right unit -> case checkUnit pol (maybe ProgramsOfConfiguration ProgramNamed (rqProgram rq)) unit of
    Left _ -> Right accepted
    Right prog -> runnable unit prog
  where
    scans = length (rqCalls rq)
    accepted = Run scans 4 []
    runnable unit prog = do
      mapM_ noInputs (rqCalls rq)
      if M.null (prInit (rqPlc rq)) then Right () else Left "ironplcvm has no way to set a direct address before the first cycle"
      if null (obsOperands (rqObserve rq)) then Right () else Left "ironplcvm's dump shows no direct addresses"
      let programs = [p | DPou p <- unitDecls unit, pouKind p == KProgram]
      if length programs <= 1 && length (prRoots prog) <= 1
        then Right ()
        else Left "ironplcvm runs one program, and the case declares several"
      case clockReaders prog (rqSource rq) of
        [] -> Right ()
        n : _ -> Left ("the program reads the clock (" <> n <> "), and ironplcvm has only the wall clock")
      observed <- mapM (observe prog) (obsVars (rqObserve rq))
      let interval = maybe 0 (`div` 1000) (prTaskInterval prog)
      Right (Run scans (4 + fromInteger interval * scans) observed)
    noInputs c
      | Just r <- callReset c = Left ("ironplcvm has no controller reset (" <> r <> ")")
      | M.null (callSet c) = Right ()
      | otherwise = Left "ironplcvm has no way to write a variable between cycles"

-- | ironplcc's dialect: its CODESYS dialect where the case's has CODESYS's
-- extensions, else strict edition 2 with what the IEC dialects add to it:
-- @//@ comments (TC-LEX-6) and VAR_GLOBAL blocks outside a configuration,
-- as the corpus's cases write them.
dialectFlags :: Policies -> [String]
dialectFlags pol = case pExtensions pol of
  ExtensionsCodesys -> ["--dialect", "codesys"]
  ExtensionsNone -> ["--allow-top-level-var-global", "--allow-c-style-comments"]

-- | What in the program reads the clock: an instance of a standard FB that
-- does, or a call of TIME().
clockReaders :: Program -> Text -> [Text]
clockReaders prog src =
  [t | pou <- M.elems (prPous prog), v <- pdVars pou, t <- fbTypes (viType v), t `elem` clockFBs]
    ++ ["TIME()" | callsTime (T.toUpper src)]
  where
    clockFBs = ["TON", "TOF", "TP", "RTC"]
    fbTypes = \case
      TFB n -> [key n]
      TArray _ t -> fbTypes t
      TStruct _ fs -> concatMap (fbTypes . snd) fs
      _ -> []
    -- a TIME that starts a word and is followed by a parenthesis (not
    -- DINT_TO_TIME(...), nor a TIME declaration beside such a call)
    callsTime s = or [(T.null before || not (identChar (T.last before))) && "(" `T.isPrefixOf` T.stripStart (T.drop 4 rest) | (before, rest) <- T.breakOnAll "TIME" s]
    identChar c = isAlphaNum c || c == '_'

-- | A path's name in the dump: a global, or a variable of the one program
-- (a VAR_EXTERNAL is the global it names). The dump lists the globals
-- first and the program's variables next, so a name is found by its first
-- line, as long as no global and program variable share it.
observe :: Program -> Text -> Either Text (Text, Text, Type)
observe prog path = do
  steps <- parseVarPath path
  (name, ty) <- case steps of
    [StepField g] | Just v <- global g -> Right (viKey v, viType v)
    [StepField root, StepField k]
      | Just t <- lookup root [(key n, t) | (n, t) <- prRoots prog]
      , Just pou <- lookupPou prog t
      , Just v <- varByKey pou k ->
          if viSection v == SecExternal || null (global k)
            then Right (viKey v, viType v)
            else Left (path <> ": the dump names a global and a program variable alike, " <> viName v)
    _ -> Left (path <> ": ironplcvm's dump shows only the globals and the program's own variables")
  if readable ty then Right (path, name, ty) else Left (path <> ": ironplcvm's dump does not show a value of " <> typeText ty)
  where
    global k = find ((== k) . viKey) (prGlobals prog)
    readable t = case t of
      TEnum {} -> True
      -- every elementary type but LTIME, whose dump loses the nanoseconds
      _ | Just e <- baseElem t -> e /= LTIME
      _ -> False

------------------------------------------------------------------------------
-- Answers

-- | ironplcc did not compile the program: its first problem. IronPLC
-- writes @error[P0002]: message@ and, a line later, @┌─ file:LINE:COL@;
-- its P9 codes say what it has not implemented, not what is wrong.
compileAnswer :: Int -> Text -> Answer
compileAnswer status err
  | status > 128 || status < 0 = AnswerRejected Nothing Nothing ("ironplcc stopped with signal " <> tshow (if status > 128 then status - 128 else negate status) <> " (it crashed) while compiling the program")
  | otherwise = case problems (T.lines (stripAnsi err)) of
      (code, msg, place, label) : _
        | code `elem` ["P9001", "P9003", "P9999"] -> AnswerUnsupported ("IronPLC has not implemented this: " <> code <> " " <> msg <> maybe "" (": " <>) label)
        | otherwise -> AnswerRejected (place >>= \(f, l) -> if f == caseFile then Just l else Nothing) Nothing (code <> ": " <> msg)
      [] -> AnswerRejected Nothing Nothing (T.strip (T.take 500 (stripAnsi err)))
  where
    problems = \case
      l : rest
        | Just r <- T.stripPrefix "error[" (T.strip l)
        , (code, msg) <- T.breakOn "]" r ->
            let near = takeWhile (not . ("error[" `T.isPrefixOf`) . T.strip) (take 8 rest)
             in (code, T.strip (T.dropWhile (`elem` [']', ':']) msg), listToMaybe (mapMaybe location near), listToMaybe (mapMaybe caretLabel near)) : problems rest
        | otherwise -> problems rest
      [] -> []
    -- the text beside the carets that mark the place: what is wrong there
    caretLabel l = case T.strip (T.dropWhile (/= '^') l) of
      t | "^" `T.isPrefixOf` t, lbl <- T.strip (T.dropWhile (== '^') t), not (T.null lbl) -> Just lbl
      _ -> Nothing
    location l = case T.stripPrefix "┌─" (T.strip l) of
      Just p -> case reverse (T.splitOn ":" (T.strip p)) of
        _col : line : file | Right (n, "") <- TR.decimal line -> Just (T.takeWhileEnd (/= '/') (T.intercalate ":" (reverse file)), n)
        _ -> Nothing
      Nothing -> Nothing

-- | Terminal colour codes out (IronPLC writes them even into a pipe).
stripAnsi :: Text -> Text
stripAnsi t = case T.breakOn "\ESC[" t of
  (a, b)
    | T.null b -> a
    | otherwise -> a <> stripAnsi (T.drop 1 (T.dropWhile (\c -> isDigit c || c == ';') (T.drop 2 b)))

-- | How the VM's run ended.
data RunOutcome
  = Finished Int Text Text -- ^ exit status, standard output, standard error
  | TimedOut -- ^ it ran past the time limit: a cycle that does not end

-- | The answer from the VM's run; Left: the run failed in a way that says
-- nothing of the program (the runner records @engine-error@).
runAnswer :: Plan -> RunOutcome -> Either Text Answer
runAnswer pl outcome = case planRun pl of
  Left why -> Right (AnswerUnsupported why)
  Right r -> case outcome of
    TimedOut -> Right (AnswerRun VerdictRuntimeError emptyObservation {obError = Just (report "watchdog")})
    Finished status out err ->
      let dump = [(key (T.strip n), T.strip (T.drop 1 v)) | l <- T.lines out, let (n, v) = T.breakOn ":" l, not (T.null v)]
          vars = M.fromList [(path, valueScalar v) | (path, name, ty) <- runObserved r, Just raw <- [lookup name dump], Just v <- [dumpValue ty raw]]
          missing = [path | (path, _, _) <- runObserved r, not (M.member path vars)]
          trap = listToMaybe [c | w <- T.words (stripAnsi err), let c = T.takeWhile isAlphaNum w, "V" `T.isPrefixOf` c, T.length c == 5]
       in case (status, trap) of
            (0, _) | null missing -> Right (AnswerRun VerdictOk (Observation M.empty vars M.empty Nothing))
            (1, Just code)
              | "V4" `T.isPrefixOf` code || "V9" `T.isPrefixOf` code ->
                  Right (AnswerRun VerdictRuntimeError (Observation M.empty vars M.empty (Just (report (trapKind code)))))
            -- Rust's panic: the VM crashed on the program
            (101, _) -> Right (AnswerRun VerdictRuntimeError emptyObservation {obError = Just (report "crash")})
            _
              | not (null missing) && status == 0 -> Left ("ironplcvm's dump has no readable value for " <> T.intercalate ", " missing)
              | otherwise -> Left ("ironplcvm ended with status " <> tshow status <> ": " <> T.take 300 (T.strip (stripAnsi err)))
  where
    report k = ErrorReport Nothing (Just k) Nothing Nothing

-- | The kind of runtime error (corpus-format §4.3) of an IronPLC trap.
trapKind :: Text -> Text
trapKind = \case
  "V4001" -> "division-by-zero"
  "V4003" -> "watchdog"
  "V4004" -> "null-pointer"
  "V4005" -> "index-out-of-range"
  "V9012" -> "call-depth"
  code -> "ironplc-" <> T.toLower code

-- | A value of a type as the dump writes it: TRUE/FALSE, decimal integers,
-- bit strings as @16#...@, reals as Rust prints them, @T#...ms@, DATE and
-- DT as seconds since 1970, TOD as milliseconds, an enumeration's value by
-- its position.
dumpValue :: Type -> Text -> Maybe Value
dumpValue ty raw = case ty of
  TEnum n vs -> (\i -> VEnum n (if i >= 0 && i < length vs then vs !! i else tshow i)) <$> int
  _ -> baseElem ty >>= \e -> case e of
    BOOL -> case raw of
      "TRUE" -> Just (VBool True)
      "FALSE" -> Just (VBool False)
      _ -> Nothing
    REAL -> VReal <$> real
    LREAL -> VLReal <$> real
    TIME -> VTime TIME <$> (T.stripPrefix "T#" raw >>= T.stripSuffix "ms" >>= intOf)
    DATE -> VDate . (* 1000) <$> int
    DT -> VDT . (* 1000) <$> int
    TOD -> VTod <$> int
    _
      | isInt e -> VInt e . wrapInt e <$> maybe int intOfHex (T.stripPrefix "16#" raw)
      | otherwise -> Nothing
  where
    int :: Num n => Maybe n
    int = fromInteger <$> intOf raw
    intOf t = case TR.signed TR.decimal t of
      Right (n, "") -> Just n
      _ -> Nothing
    intOfHex t = case TR.hexadecimal t of
      Right (n, "") -> Just n
      _ -> Nothing
    real :: (Read f, RealFloat f) => Maybe f
    real = case raw of
      "NaN" -> Just (0 / 0)
      "inf" -> Just (1 / 0)
      "-inf" -> Just (-1 / 0)
      _ -> readMaybe (T.unpack (fixReal raw))
    -- Rust writes 1e-7 as 0.0000001 and 1e38 in full; Haskell's reader
    -- wants a digit before and after the point
    fixReal t
      | "-" `T.isPrefixOf` t = "-" <> fixReal (T.drop 1 t)
      | "." `T.isPrefixOf` t = "0" <> t
      | otherwise = T.dropWhileEnd isSpace t

tshow :: Show a => a -> Text
tshow = T.pack . show
