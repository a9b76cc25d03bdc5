-- | The MATIEC adapter (docs/engines.md): how a case of an IEC dialect
-- becomes a program MATIEC's @iec2c@ compiles, a C driver of stref's own
-- that runs it over the case's cycles on the virtual clock, and how the
-- driver's output and iec2c's messages become a stref-engine/1 answer.
--
-- Everything here is pure; "Stref.Engines.Run" runs the tools. The same
-- adapter serves MATIEC and OpenPLC's fork of it, which share their output.
--
-- * The source keeps its lines: top-level VAR_GLOBAL blocks are blanked
--   and moved into a CONFIGURATION (appended when the case has none, with
--   one task at the case's cycle running its program), and every PROGRAM
--   and FUNCTION_BLOCK gets, on its header's line, the VAR_EXTERNAL
--   declarations MATIEC needs to reach them. So iec2c's line numbers are
--   the case's.
-- * The driver sets the clock to (k - 1) × the task interval before cycle
--   k (corpus-format §4.1), writes the cycle's variables, runs
--   @config_run__@, and after the last cycle (or a trap: SIGFPE, SIGSEGV)
--   prints every observed value as raw data: integers, the bit patterns of
--   REAL and LREAL, times in nanoseconds, a string's bytes.
module Stref.Engines.Matiec
  ( Plan (..)
  , Observed (..)
  , plan
  , driverSource
  , locatedNames
  , compileAnswer
  , runAnswer
  , RunOutcome (..)
  , caseFile
  , decodeRaw
  , driverAnswer
  ) where

import Data.Bits (shiftR, (.&.))
import Data.Char (isAlphaNum, isSpace, ord)
import Data.List (elemIndex, find, foldl')
import qualified Data.Map.Strict as M
import Data.Maybe (fromMaybe, mapMaybe)
import qualified Data.Sequence as Seq
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Read as TR
import GHC.Float (castDoubleToWord64, castFloatToWord32, castWord32ToFloat, castWord64ToDouble)
import Numeric (showHex)
import Stref.Conformance.Protocol
import Stref.IEC.Check (ProgramChoice (..), checkUnit, locationType)
import Stref.IEC.Checked
import Stref.IEC.Engine (locationOf, parseVarPath, scalarValue, valueScalar)
import Stref.IEC.Parser (parseUnit)
import Stref.IEC.Syntax
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy (Policies)

-- | What to compile and how to drive it.
data Plan = Plan
  { planSource :: Text -- ^ the ST file given to iec2c
  , planConfigHeader :: Text -- ^ the header iec2c writes for the configuration (its accessors of globals)
  , planInstances :: [(Text, Text)] -- ^ C symbol of each program instance and its C type
  , planCycles :: [[(Text, Scalar)]] -- ^ the variables written before each cycle
  , planInit :: [(Text, Scalar)] -- ^ located variables before the first cycle
  , planObserved :: [(Text, Observed)] -- ^ each observed path
  , planWritten :: [(Text, Observed)] -- ^ each path written before a cycle
  , planPolicies :: Policies
  }

-- | How a path is reached in C, and its type.
data Observed
  = ObsVar Text Type -- ^ a C lvalue
  | ObsLocated Location -- ^ a direct address, if the program declares it
  | ObsUnknown Text -- ^ why the driver cannot observe it

------------------------------------------------------------------------------
-- The plan

-- | The plan for a request, or why the adapter cannot run it (an
-- @unsupported@ answer).
plan :: Policies -> Request -> Either Text Plan
plan pol rq = do
  calls <- mapM cycleOf (rqCalls rq)
  unit <- either (const (Right Nothing)) (Right . Just) (parseUnit pol "case.st" (rqSource rq))
  let checked = unit >>= either (const Nothing) Just . checkUnit pol (maybe ProgramsOfConfiguration ProgramNamed (rqProgram rq))
      cycle = fromMaybe "T#10ms" (rqCycle rq)
  case unit of
    -- stref cannot read the case: iec2c gets it as it is, to say what it
    -- makes of it
    Nothing -> Right (Plan (rqSource rq) "" [] calls [] [] [] pol)
    Just u -> do
      let (source, header, instances) = transform (rqSource rq) u checked (rqProgram rq) cycle
          paths ps = case checked of
            Just prog -> [(p, observe pol prog instances p) | p <- ps]
            Nothing -> []
          observed = paths (obsVars (rqObserve rq) ++ obsOperands (rqObserve rq))
          written = paths (M.keys (M.unions (map callSet (rqCalls rq))))
      Right (Plan source header [(sym, ty) | (_, sym, ty) <- instances] calls (M.toList (prInit (rqPlc rq))) observed written pol)
  where
    cycleOf c = case callReset c of
      Nothing -> Right (M.toList (callSet c))
      Just r -> Left ("the MATIEC driver has no controller reset (" <> r <> "): it runs the program from its start only")

-- | The source to compile, the configuration's header, and each program
-- instance: the name paths use, its C symbol, its C type.
transform :: Text -> Unit -> Maybe Program -> Maybe Text -> Text -> (Text, Text, [(Text, Text, Text)])
transform src (Unit decls) checked program cycle =
  let globalBlocks = [b | DGlobals b <- decls]
      spans = [(b, blockSpan src (vbPos b)) | b <- globalBlocks]
      blanked = foldl' (\s (_, (a, z)) -> blank a z s) src spans
      moved = T.intercalate " " [oneLine (T.take (z - a) (T.drop a src)) | (_, (a, z)) <- spans]
      globalsMoved = [(d, b) | b <- globalBlocks, d <- vbDecls b]
      externals pou =
        let own = [key n | vb <- pouVars pou, d <- vbDecls vb, (_, n) <- vdNames d]
            wanted = [(n, b, ty) | (d, b) <- globalsMoved, (_, n) <- vdNames d, key n `notElem` own, Just ty <- [globalTypeText n]]
         in if null wanted
              then ""
              else T.concat [" VAR_EXTERNAL" <> (if vbConstant b then " CONSTANT " else " ") <> n <> " : " <> ty <> "; END_VAR" | (n, b, ty) <- wanted] <> " "
      globalTypeText n = checked >>= \prog -> find ((== key n) . viKey) (prGlobals prog) >>= stType . viType
      pous = [p | DPou p <- decls, pouKind p `elem` [KProgram, KFunctionBlock]]
      withExternals = foldl' (\s p -> insertAfterHeader (pouPos p) (externals p) s) blanked (reverse (sortOnPos pous))
      configs = [c | DConfig c <- decls]
   in case configs of
        c : _ ->
          let withGlobals = insertAfterHeader (cfgPos c) (if T.null moved then "" else " " <> moved <> " ") withExternals
              instances = [(pcInstance pc, cName (resName r) <> "__" <> cName (pcInstance pc), cName (pcType pc)) | r <- cfgResources c, pc <- resPrograms r]
           in (withGlobals, cfgName c <> ".h", instances)
        [] ->
          let prog = fromMaybe "MAIN" (program `orElse` (checked >>= \p -> fst <$> safeHead (prInstances p)) `orElse` safeHead [pouName p | p <- pous, pouKind p == KProgram])
              wrapper =
                T.unlines
                  [ ""
                  , "CONFIGURATION StrefConfig"
                  , "  " <> moved
                  , "  RESOURCE StrefResource ON PLC"
                  , "    TASK StrefTask(INTERVAL := " <> cycle <> ", PRIORITY := 0);"
                  , "    PROGRAM StrefMain WITH StrefTask : " <> prog <> ";"
                  , "  END_RESOURCE"
                  , "END_CONFIGURATION"
                  ]
           in (withExternals <> wrapper, "StrefConfig.h", [(prog, "STREFRESOURCE__STREFMAIN", cName prog)])
  where
    orElse a b = maybe b Just a
    safeHead = \case
      x : _ -> Just x
      [] -> Nothing
    sortOnPos = foldr insertPos []
    insertPos p [] = [p]
    insertPos p (q : qs) = if posKey (pouPos p) <= posKey (pouPos q) then p : q : qs else q : insertPos p qs
    posKey (Pos l c) = (l, c)

-- | The C name of an ST name: upper case.
cName :: Text -> Text
cName = T.toUpper

-- | A type as ST text, for a VAR_EXTERNAL.
stType :: Type -> Maybe Text
stType = \case
  TElem e -> Just (elemName e)
  TString False _ -> Just "STRING"
  TString True _ -> Just "WSTRING"
  TArray bs t -> (\tt -> "ARRAY [" <> T.intercalate ", " [tshow lo <> ".." <> tshow hi | (lo, hi) <- bs] <> "] OF " <> tt) <$> stType t
  TStruct n _ | not (T.null n) -> Just n
  TEnum n _ | not (T.null n) -> Just n
  TSubrange e lo hi -> Just (elemName e <> " (" <> tshow lo <> ".." <> tshow hi <> ")")
  TFB n -> Just n
  _ -> Nothing

-- | The offsets of a VAR_GLOBAL block: its keyword to the end of its END_VAR.
blockSpan :: Text -> Pos -> (Int, Int)
blockSpan src p =
  let a = offsetOf src p
      rest = T.toUpper (T.drop a src)
      (before, found) = T.breakOn "END_VAR" rest
   in (a, if T.null found then T.length src else a + T.length before + 7)

-- | The offset of a line and column (both from 1).
offsetOf :: Text -> Pos -> Int
offsetOf src (Pos l c) = sum [T.length x + 1 | x <- take (l - 1) (T.splitOn "\n" src)] + c - 1

-- | Spaces for the characters between two offsets, newlines kept.
blank :: Int -> Int -> Text -> Text
blank a z s = T.take a s <> T.map (\c -> if c == '\n' || c == '\r' then c else ' ') (T.take (z - a) (T.drop a s)) <> T.drop z s

-- | Text moved onto one line (a block with a line comment keeps its lines).
oneLine :: Text -> Text
oneLine t = if "//" `T.isInfixOf` t then t else T.map (\c -> if c == '\n' || c == '\r' then ' ' else c) t

-- | Text inserted after the keyword and name that start at a position.
insertAfterHeader :: Pos -> Text -> Text -> Text
insertAfterHeader p ins src
  | T.null ins = src
  | otherwise =
      let a = offsetOf src p
          rest = T.drop a src
          kw = T.takeWhile isWord rest
          afterKw = T.drop (T.length kw) rest
          gap = T.takeWhile isSpace afterKw
          name = T.takeWhile isWord (T.drop (T.length gap) afterKw)
          at = a + T.length kw + T.length gap + T.length name
       in T.take at src <> ins <> T.drop at src
  where
    isWord c = isAlphaNum c || c == '_'

------------------------------------------------------------------------------
-- Paths to C

observe :: Policies -> Program -> [(Text, Text, Text)] -> Text -> Observed
observe pol prog instances path
  | "%" `T.isPrefixOf` path = either ObsUnknown ObsLocated (locationOf pol path)
  | otherwise = either ObsUnknown (uncurry ObsVar) (parseVarPath path >>= access prog instances)

-- | The C lvalue of a variable path and its type.
access :: Program -> [(Text, Text, Text)] -> [Step] -> Either Text (Text, Type)
access prog instances = \case
  StepField root : rest
    | Just (_, sym, _) <- find (\(n, _, _) -> key n == root) instances
    , Just t <- lookup root [(key n, t) | (n, t) <- prInstances prog] `orElse` lookup root [(key n, t) | (n, t) <- prRoots prog] ->
        walk (sym, TProgram t) rest
    | Just v <- find ((== root) . viKey) (prGlobals prog) -> walk ("(*__GET_GLOBAL_" <> viKey v <> "())", viType v) rest
  _ -> Left "the path names neither the program instance the driver runs nor a global"
  where
    orElse a b = maybe b Just a
    walk (e, t) [] = Right (e, t)
    walk (e, t) (s : rest) = case (s, t) of
      (StepField k, TProgram n) -> member e n k >>= (`walk` rest)
      (StepField k, TFB n) -> member e n k >>= (`walk` rest)
      (StepField k, TStruct _ fs) | Just ft <- lookup k [(key f, ft) | (f, ft) <- fs] -> walk (e <> "." <> k, ft) rest
      (StepIndex is, TArray bs et) | length is == length bs, and [i >= lo && i <= hi | (i, (lo, hi)) <- zip is bs] ->
        walk (e <> ".table" <> T.concat ["[" <> tshow (i - lo) <> "]" | (i, (lo, _)) <- zip is bs], et) rest
      _ -> Left "the path goes where the driver cannot follow it"
    -- a POU's variable is a value with flags (@.value@); a located or
    -- external one points at its value; an FB instance is a plain member
    member e n k = case lookupPou prog n >>= (`varByKey` k) of
      Just v -> Right $ case viType v of
        TFB _ -> (e <> "." <> k, viType v)
        _ | viAt v /= Nothing || viSection v == SecExternal -> ("(*" <> e <> "." <> k <> ".value)", viType v)
        _ -> (e <> "." <> k <> ".value", viType v)
      Nothing -> Left ("no variable " <> k <> " in " <> n)

-- | The scalar parts of a value of a type, in order, as C lvalues.
leaves :: (Text, Type) -> Either Text [(Text, Type)]
leaves (e, t) = case t of
  TArray bs et -> concat <$> mapM (\ix -> leaves (e <> ".table" <> T.concat ["[" <> tshow i <> "]" | i <- ix], et)) (indices bs)
  TStruct _ fs -> concat <$> mapM (\(f, ft) -> leaves (e <> "." <> key f, ft)) fs
  TFB _ -> Left "a whole function block instance"
  TProgram _ -> Left "a whole program instance"
  TUnion {} -> Left "a union"
  TPointer _ -> Right [(e, TElem DWORD)]
  _ -> Right [(e, t)]
  where
    indices bs = sequence [[0 .. hi - lo] | (lo, hi) <- bs]

------------------------------------------------------------------------------
-- The driver

-- | The symbols of the direct addresses the program declares, from iec2c's
-- LOCATED_VARIABLES.h (MATIEC writes stray text around them).
locatedNames :: Text -> [(Text, Text)]
locatedNames h = mapMaybe entry (drop 1 (T.splitOn "__LOCATED_VAR(" h))
  where
    entry t = case T.splitOn "," (T.takeWhile (/= ')') t) of
      ty : name : _ -> Just (T.strip name, T.strip ty)
      _ -> Nothing

-- | The C symbol of a direct address: @%IX0.1@ is @__IX0_1@.
locatedSymbol :: Location -> Text
locatedSymbol l = "__" <> T.replace "." "_" (T.drop 1 (locText l))

-- | The driver's C source, given the direct addresses the program
-- declares (symbol, C type).
driverSource :: Plan -> [(Text, Text)] -> Either Text Text
driverSource pl located = do
  observed <- concat <$> mapM observedLeaves (planObserved pl)
  inits <- mapM assignment (planInit pl)
  perCycle <- mapM (mapM assignment) (planCycles pl)
  Right . T.unlines $
    [ "/* stref's driver for a program compiled by iec2c (generated) */"
    , "#include <setjmp.h>"
    , "#include <signal.h>"
    , "#include <stdint.h>"
    , "#include <stdio.h>"
    , "#include <string.h>"
    , "#include <unistd.h>"
    , "#include \"iec_std_lib.h\""
    , "#include \"POUS.h\""
    ]
      ++ ["#include \"" <> planConfigHeader pl <> "\"" | not (T.null (planConfigHeader pl))]
      ++ [ty <> " __stref_at" <> name <> "; " <> ty <> " *" <> name <> " = &__stref_at" <> name <> ";" | (name, ty) <- located]
      ++ [ "TIME __CURRENT_TIME;"
         , "BOOL __DEBUG;"
         , "extern unsigned long long common_ticktime__;"
         , "void config_init__(void);"
         , "void config_run__(unsigned long tick);"
         ]
      ++ ["extern " <> ty <> " " <> sym <> ";" | (sym, ty) <- planInstances pl]
      ++ [ "static sigjmp_buf trap;"
         , "static volatile sig_atomic_t caught;"
         , "static void on_signal(int s) { caught = s; siglongjmp(trap, 1); }"
         , "static TIME at_ns(long long ns) { TIME t; t.tv_sec = (long)(ns / 1000000000LL); t.tv_nsec = (long)(ns % 1000000000LL); return t; }"
         , "static long long ns_of(TIME t) { return (long long)t.tv_sec * 1000000000LL + (long long)t.tv_nsec; }"
         , "static REAL real_of(uint32_t u) { REAL f; memcpy(&f, &u, 4); return f; }"
         , "static LREAL lreal_of(uint64_t u) { LREAL f; memcpy(&f, &u, 8); return f; }"
         , "static STRING string_of(const char *s, int n) { STRING r; memset(&r, 0, sizeof r); r.len = n; memcpy(r.body, s, n); return r; }"
         , "static void put_real(REAL f) { uint32_t u; memcpy(&u, &f, 4); printf(\"= %lu\\n\", (unsigned long)u); }"
         , "static void put_lreal(LREAL f) { uint64_t u; memcpy(&u, &f, 8); printf(\"= %llu\\n\", (unsigned long long)u); }"
         , "static void put_string(STRING s) { int n = (unsigned char)s.len; printf(\"= %d\", n); for (int i = 0; i < n && i < STR_MAX_LEN; i++) printf(\" %u\", (unsigned)(unsigned char)s.body[i]); printf(\"\\n\"); }"
         , "static void before_cycle(int k) {"
         , "  switch (k) {"
         ]
      ++ concat [["  case " <> tshow k <> ":"] ++ map ("    " <>) sets ++ ["    break;"] | (k, sets) <- zip [1 :: Int ..] perCycle, not (null sets)]
      ++ [ "  default: break;"
         , "  }"
         , "}"
         , "int main(void) {"
         , "  volatile int k = 0;"
         , "  signal(SIGFPE, on_signal);"
         , "  signal(SIGSEGV, on_signal);"
         , "  signal(SIGALRM, on_signal);"
         , "  alarm(" <> tshow watchdogSeconds <> ");"
         , "  __CURRENT_TIME = at_ns(0);"
         , "  config_init__();"
         ]
      ++ map ("  " <>) inits
      ++ [ "  if (sigsetjmp(trap, 1) == 0) {"
         , "    for (k = 1; k <= " <> tshow (length (planCycles pl)) <> "; k++) {"
         , "      before_cycle(k);"
         , "      __CURRENT_TIME = at_ns((long long)(k - 1) * (long long)common_ticktime__);"
         , "      config_run__((unsigned long)(k - 1));"
         , "    }"
         , "  } else {"
         , "    signal(SIGFPE, SIG_DFL);"
         , "    signal(SIGSEGV, SIG_DFL);"
         , "    alarm(0);"
         , "    printf(\"trap %d %d\\n\", (int)caught, (int)k);"
         , "  }"
         ]
      ++ map ("  " <>) observed
      ++ [ "  printf(\"end\\n\");"
         , "  return 0;"
         , "}"
         ]
  where
    locatedLvalue l = case lookup (locatedSymbol l) located of
      Just _ -> Right ("(*" <> locatedSymbol l <> ")", locationType l)
      Nothing -> Left ("the program declares no variable at " <> locText l <> ", so the driver has nothing to read or write there")
    lvalueOf path = case lookup path (planWritten pl ++ planObserved pl) of
      Just (ObsVar e t) -> Right (e, t)
      Just (ObsLocated l) -> locatedLvalue l
      Just (ObsUnknown why) -> Left why
      Nothing
        | "%" `T.isPrefixOf` path -> locationOf (planPolicies pl) path >>= locatedLvalue
        | otherwise -> Left ("the path " <> path <> " is not one the driver can write")
    observedLeaves (path, o) = do
      lv <- case o of
        ObsVar e t -> Right (e, t)
        ObsLocated l -> locatedLvalue l
        ObsUnknown why -> Left (path <> ": " <> why)
      either (\why -> Left (path <> ": " <> why <> " cannot be observed")) (Right . map printLeaf) (leaves lv)
    assignment (path, s) = do
      (e, t) <- lvalueOf path
      v <- either (\m -> Left (path <> ": " <> m)) Right (scalarValue (planPolicies pl) t s)
      r <- cValue t v
      Right (e <> " = " <> r <> ";")

-- | The watchdog of the driver's whole run: the cycles that have not ended
-- by then are a @watchdog@ error, as a task watchdog stops a controller.
watchdogSeconds :: Int
watchdogSeconds = 2

printLeaf :: (Text, Type) -> Text
printLeaf (e, t) = case t of
  TElem REAL -> "put_real(" <> e <> ");"
  TElem LREAL -> "put_lreal(" <> e <> ");"
  TElem x | x `elem` [TIME, LTIME, DATE, TOD, DT] -> "printf(\"= %lld\\n\", ns_of(" <> e <> "));"
  TString {} -> "put_string(" <> e <> ");"
  _ | Just x <- baseElem t, isInt x, not (isSignedInt x) -> "printf(\"= %llu\\n\", (unsigned long long)(" <> e <> "));"
  _ -> "printf(\"= %lld\\n\", (long long)(" <> e <> "));"

-- | A value as a C expression of its type.
cValue :: Type -> Value -> Either Text Text
cValue t v = case v of
  VBool b -> Right (if b then "1" else "0")
  VInt e n
    | isSignedInt e -> Right ("((long long)" <> signedLit n <> ")")
    | otherwise -> Right ("0x" <> T.pack (showHex n "") <> "ULL")
  VReal f -> Right ("real_of(0x" <> T.pack (showHex (castFloatToWord32 f) "") <> "UL)")
  VLReal d -> Right ("lreal_of(0x" <> T.pack (showHex (castDoubleToWord64 d) "") <> "ULL)")
  VTime TIME ms -> ns (ms * 1000000)
  VTime _ n -> ns n
  VDate ms -> ns (ms * 1000000)
  VTod ms -> ns (ms * 1000000)
  VDT ms -> ns (ms * 1000000)
  VString s -> Right ("string_of(\"" <> T.concat [T.pack ("\\" <> octal (ord c)) | c <- T.unpack s] <> "\", " <> tshow (T.length s) <> ")")
  VEnum _ x | TEnum _ vs <- t, Just i <- elemIndex x vs -> Right (tshow i)
  _ -> Left ("a value of " <> typeText t <> " the driver cannot write")
  where
    ns n = Right ("at_ns(" <> signedLit n <> ")")
    signedLit n
      | n == negate (2 ^ (63 :: Int)) = "(-9223372036854775807LL - 1)"
      | otherwise = tshow n <> "LL"
    octal c = [toEnum (48 + (c `shiftR` 6) .&. 7), toEnum (48 + (c `shiftR` 3) .&. 7), toEnum (48 + c .&. 7)]

------------------------------------------------------------------------------
-- Answers

-- | The name of the file the adapter gives iec2c.
caseFile :: Text
caseFile = "case.st"

-- | iec2c did not compile the program: its first message with a line.
-- MATIEC writes @file:LINE-COL..LINE-COL: error: message@ or
-- @file:LINE: error: message@.
compileAnswer :: Int -> Text -> Answer
compileAnswer status stderr
  | status > 128 || status < 0 = AnswerRejected Nothing Nothing ("iec2c stopped with signal " <> tshow (if status > 128 then status - 128 else negate status) <> " (it crashed) while compiling the program")
  | otherwise = case mapMaybe located (T.lines stderr) of
      (file, l, m) : _
        | file == caseFile -> AnswerRejected (Just l) Nothing m
        -- an error in the engine's own library, which the program's names
        -- can provoke (a type named like a standard FB's input)
        | otherwise -> AnswerRejected Nothing Nothing (file <> ":" <> tshow l <> ": " <> m)
      [] -> AnswerRejected Nothing Nothing (T.strip (T.take 500 stderr))
  where
    located ln = case T.breakOn ": error: " ln of
      (loc, msg) | not (T.null msg) ->
        let (file, place) = T.breakOnEnd ":" loc
         in case TR.decimal place of
              Right (n, _) -> Just (T.takeWhileEnd (/= '/') (T.dropEnd 1 file), n, T.strip (T.drop 9 msg))
              Left _ -> Nothing
      _ -> Nothing

-- | How the driver's run ended.
data RunOutcome
  = Finished Text -- ^ its standard output
  | TimedOut -- ^ it ran past the time limit: a cycle that does not end

-- | The answer from the driver's output.
runAnswer :: Plan -> RunOutcome -> Answer
runAnswer pl = driverAnswer (\raws -> M.fromList (fst (foldl' decodeOne ([], raws) (planObserved pl))))
  where
    decodeOne (acc, raws) (path, o) = case typeOf o of
      Just t ->
        let n = either (const 0) length (leaves ("", t))
            (mine, rest) = splitAt n raws
         in case decodeRaw t mine of
              Just (v, []) -> ((path, valueScalar v) : acc, rest)
              _ -> (acc, rest)
      Nothing -> (acc, raws)
    typeOf = \case
      ObsVar _ t -> Just t
      ObsLocated l -> Just (locationType l)
      ObsUnknown _ -> Nothing

-- | The answer from the output of a driver of stref's own (the MATIEC and
-- the RuSTy drivers print alike): @trap SIGNAL CYCLE@ when a signal stopped
-- the cycles, a @= RAW@ line per leaf of the observed values (which the
-- caller decodes), and @end@. Without @end@ the driver itself died.
driverAnswer :: ([Text] -> M.Map Text Scalar) -> RunOutcome -> Answer
driverAnswer decode = \case
  TimedOut -> AnswerRun VerdictRuntimeError emptyObservation {obError = Just (report "watchdog")}
  Finished out ->
    let ls = T.lines out
        trap = case [T.words (T.drop 5 l) | l <- ls, "trap " `T.isPrefixOf` l] of
          [s, _] : _ -> Just (signalKind s)
          _ -> Nothing
        vars = decode [T.drop 2 l | l <- ls, "= " `T.isPrefixOf` l]
     in if "end" `elem` ls
          then AnswerRun (maybe VerdictOk (const VerdictRuntimeError) trap) (Observation M.empty vars M.empty (report <$> trap))
          else AnswerRun VerdictRuntimeError emptyObservation {obError = Just (report (fromMaybe "crash" trap))}
  where
    report k = ErrorReport Nothing (Just k) Nothing Nothing
    signalKind s
      | s == "8" = "division-by-zero" -- SIGFPE: the integer division traps
      | s == "14" = "watchdog" -- SIGALRM: the cycles ran past the watchdog
      | otherwise = "crash" -- SIGSEGV; SIGABRT (a panic in RuSTy's library)

-- | A value of a type from the raw leaves a driver printed: integers in
-- decimal, REAL and LREAL as their bit patterns, the time types in
-- nanoseconds, a string as its length and bytes. (The RuSTy adapter's
-- driver prints the same.)
decodeRaw :: Type -> [Text] -> Maybe (Value, [Text])
decodeRaw t raws = case t of
  TArray bs et -> do
    let count = product [hi - lo + 1 | (lo, hi) <- bs]
    (xs, rest) <- many (fromInteger count) et raws
    Just (VArray bs (Seq.fromList xs), rest)
  TStruct _ fs -> do
    (vs, rest) <- foldl' (\m (f, ft) -> m >>= \(acc, r) -> decodeRaw ft r >>= \(v, r') -> Just (acc ++ [(key f, v)], r')) (Just ([], raws)) fs
    Just (VStruct (M.fromList vs), rest)
  _ -> case raws of
    r : rest -> (\v -> (v, rest)) <$> scalar r
    [] -> Nothing
  where
    many 0 _ rs = Just ([], rs)
    many n et rs = do
      (v, rs') <- decodeRaw et rs
      (vs, rs'') <- many (n - 1 :: Int) et rs'
      Just (v : vs, rs'')
    int r = case TR.signed TR.decimal r of
      Right (n, _) -> Just n
      Left _ -> Nothing
    scalar r = case t of
      TElem BOOL -> VBool . (/= (0 :: Integer)) <$> int r
      TElem REAL -> VReal . castWord32ToFloat . fromInteger <$> int r
      TElem LREAL -> VLReal . castWord64ToDouble . fromInteger <$> int r
      TElem TIME -> VTime TIME . (`div` 1000000) <$> int r
      TElem LTIME -> VTime LTIME <$> int r
      TElem DATE -> VDate . (`div` 1000000) <$> int r
      TElem TOD -> VTod . (`div` 1000000) <$> int r
      TElem DT -> VDT . (`div` 1000000) <$> int r
      TString {} -> case mapM (fmap fromInteger . int) (T.words r) of
        Just (n : cs) -> Just (VString (T.pack (map toEnum (take n cs))))
        _ -> Nothing
      TEnum n vs -> (\i -> VEnum n (if i >= 0 && i < toInteger (length vs) then vs !! fromInteger i else tshow i)) <$> int r
      TPointer _ -> VInt DWORD <$> int r
      _ | Just e <- baseElem t, isInt e -> VInt e . wrapInt e <$> int r
      _ -> Nothing

tshow :: Show a => a -> Text
tshow = T.pack . show
