-- | The RuSTy adapter (docs/engines.md): how a case of an IEC dialect
-- becomes an object file RuSTy's @plc@ compiles, a C driver of stref's own
-- that runs its program over the case's cycles on the virtual clock, and
-- how the driver's output and plc's messages become a stref-engine/1
-- answer.
--
-- Everything here is pure; "Stref.Engines.Run" runs the tools.
--
-- * The case's source is compiled unchanged, with a second file of probes:
--   for each variable path the case reads or writes, a function that gives
--   the variable's address (@ADR(MAIN.fb.Q)@). The driver reaches every
--   variable through its probe, so it needs no knowledge of RuSTy's data
--   layout, only of each leaf's C type.
-- * RuSTy's standard timers read the C library's @clock_gettime@; the
--   driver defines its own, which reads the virtual clock: (k - 1) × the
--   cycle during cycle k (corpus-format §4.1).
-- * The driver writes the cycle's variables, calls each program, and after
--   the last cycle (or a trap: SIGFPE, SIGSEGV, SIGABRT, the watchdog's
--   alarm) prints every observed value as raw data, as the MATIEC driver
--   does ("Stref.Engines.Matiec".decodeRaw reads both).
module Stref.Engines.Rusty
  ( Plan (..)
  , Run (..)
  , plan
  , caseFile
  , probeFile
  , driverSource
  , compileAnswer
  , RunOutcome (..)
  , runAnswer
  ) where

import Data.Bits (shiftR, (.&.))
import Data.Char (ord)
import Data.List (elemIndex, foldl')
import qualified Data.Map.Strict as M
import Data.Maybe (mapMaybe)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Read as TR
import GHC.Float (castDoubleToWord64, castFloatToWord32)
import Numeric (showHex)
import Stref.Conformance.Protocol
import Stref.Engines.Matiec (RunOutcome (..), decodeRaw, driverAnswer)
import Stref.IEC.Check (ProgramChoice (..), checkUnit)
import Stref.IEC.Checked
import Stref.IEC.Engine (cycleMillis, observedTypes, scalarValue, valueScalar)
import Stref.IEC.Parser (parseUnit)
import Stref.IEC.Syntax
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy (Policies)

-- | What to compile, and how to run it if it compiles.
data Plan = Plan
  { planSource :: Text -- ^ the case's source, unchanged
  , planProbes :: Text -- ^ the probe functions, one per path
  , planRun :: Either Text Run -- ^ how to run it, or why the driver cannot
  }

data Run = Run
  { runPrograms :: [Text] -- ^ the programs a cycle calls, in order, as declared
  , runCycleNs :: Integer -- ^ the task interval in nanoseconds
  , runCycles :: [[(Int, Type, Value)]] -- ^ before each cycle: probe, type, value written
  , runObserved :: [(Text, Int, Type)] -- ^ each observed path, its probe and type
  }

caseFile, probeFile :: Text
caseFile = "case.st"
probeFile = "stref_probes.st"

-- | The plan for a request; Left: why the adapter cannot give RuSTy the
-- case at all (@unsupported@, before compiling).
plan :: Policies -> Request -> Either Text Plan
plan pol rq = case parseUnit pol "case.st" (rqSource rq) of
  -- a case stref rejects: plc says what it makes of it, and runs nothing
  Left _ -> Right accepted
  Right unit
    | not (null [() | DConfig _ <- unitDecls unit]) -> Left "RuSTy has no CONFIGURATION, RESOURCE or TASK (plc rejects the syntax); the driver runs bare programs"
    | Just r <- firstReset -> Left ("the driver has no controller reset (" <> r <> "): RuSTy's initialisation runs once, before main")
    | otherwise -> case checkUnit pol (maybe ProgramsOfConfiguration ProgramNamed (rqProgram rq)) unit of
        Left _ -> Right accepted
        Right prog -> Right (runnable prog)
  where
    accepted = Plan (rqSource rq) "" (Right (Run [] 0 [] []))
    firstReset = case mapMaybe callReset (rqCalls rq) of
      r : _ -> Just r
      [] -> Nothing
    written = M.keys (M.unions (map callSet (rqCalls rq)))
    observed = obsVars (rqObserve rq)
    paths = observed ++ [p | p <- written, p `notElem` observed]
    probeOf = M.fromList (zip paths [0 :: Int ..])
    runnable prog =
      Plan (rqSource rq) (T.unlines [probe i p | (p, i) <- M.toList probeOf]) $ do
        if M.null (prInit (rqPlc rq)) then Right () else Left "the driver writes no direct address before the first cycle"
        if null (obsOperands (rqObserve rq)) then Right () else Left "the driver reads variables, not direct addresses"
        cycleMs <- cycleMillis pol (maybe "T#10ms" id (rqCycle rq))
        let types = observedTypes pol (rqSource rq) (rqProgram rq) paths
            typed p = maybe (Left (p <> ": the path names nothing the driver can reach")) Right (M.lookup p types)
        mapM_ (\p -> typed p >>= reachable p) paths
        obs <- mapM (\p -> (\t -> (p, probeOf M.! p, t)) <$> typed p) observed
        cycles <- mapM (\c -> mapM (write typed) (M.toList (callSet c))) (rqCalls rq)
        programs <- mapM (\(inst, t) -> if key inst == key t then Right (declaredName prog t) else Left "a program instance named apart from its type needs a CONFIGURATION") (prInstances prog)
        Right (Run programs (cycleMs * 1000000) cycles obs)
    write typed (p, s) = do
      t <- typed p
      v <- either (\m -> Left (p <> ": " <> m)) Right (scalarValue pol t s)
      Right (probeOf M.! p, t, v)
    probe i p = "FUNCTION __stref_p" <> tshow i <> " : LWORD __stref_p" <> tshow i <> " := ADR(" <> p <> "); END_FUNCTION"
    declaredName prog t = maybe t pdName (lookupPou prog t)

-- | What the driver reads and writes: a single value, or a whole array of
-- them, which RuSTy stores flat, the last index varying fastest.
reachable :: Text -> Type -> Either Text ()
reachable p t = case t of
  TArray _ et | TString {} <- et -> bad
  TArray _ et -> () <$ leafType p et
  _ -> () <$ leafType p t
  where
    bad = Left (p <> ": the driver reads and writes single values and arrays of them, not a " <> typeText t)

-- | The C type of a variable RuSTy stores, or why the driver does not
-- handle it (a structure or instance; a pointer; WSTRING).
leafType :: Text -> Type -> Either Text Text
leafType p t = case t of
  TString False _ -> Right "char"
  TEnum {} -> Right "int32_t"
  _ | Just e <- baseElem t -> case e of
    BOOL -> Right "uint8_t"
    REAL -> Right "float"
    LREAL -> Right "double"
    _
      | e `elem` [TIME, LTIME, DATE, TOD, DT] -> Right "int64_t"
      | isInt e -> Right ((if isSignedInt e then "int" else "uint") <> tshow (intBits e) <> "_t")
      | otherwise -> bad
  _ -> bad
  where
    bad = Left (p <> ": the driver reads and writes single values and arrays of them, not a " <> typeText t)

-- | The driver's C source.
driverSource :: Run -> Text
driverSource r =
  T.unlines $
    [ "/* stref's driver for a program compiled by RuSTy's plc (generated) */"
    , "#define _GNU_SOURCE"
    , "#include <setjmp.h>"
    , "#include <signal.h>"
    , "#include <stdint.h>"
    , "#include <stdio.h>"
    , "#include <string.h>"
    , "#include <time.h>"
    , "#include <unistd.h>"
    , "static int64_t virtual_ns = 0;"
    , "/* the clock the standard timers read: the virtual one (corpus-format 4.1) */"
    , "int clock_gettime(clockid_t id, struct timespec *ts) { (void)id; ts->tv_sec = virtual_ns / 1000000000LL; ts->tv_nsec = virtual_ns % 1000000000LL; return 0; }"
    ]
      ++ concat [["extern char " <> n <> "_instance[];", "extern void " <> n <> "(void *);"] | n <- runPrograms r]
      ++ ["extern uint64_t __stref_p" <> tshow i <> "(void);" | i <- probes]
      ++ [ "#define AT(i, T) ((T *)(uintptr_t)(i))"
         , "static sigjmp_buf trap;"
         , "static volatile sig_atomic_t caught;"
         , "static void on_signal(int s) { caught = s; siglongjmp(trap, 1); }"
         , "static void put_real(float f) { uint32_t u; memcpy(&u, &f, 4); printf(\"= %lu\\n\", (unsigned long)u); }"
         , "static void put_lreal(double f) { uint64_t u; memcpy(&u, &f, 8); printf(\"= %llu\\n\", (unsigned long long)u); }"
         , "static void put_string(const char *s, int cap) { int n = 0; while (n < cap && s[n]) n++; printf(\"= %d\", n); for (int i = 0; i < n; i++) printf(\" %u\", (unsigned)(unsigned char)s[i]); printf(\"\\n\"); }"
         , "static void before_cycle(int k) {"
         , "  switch (k) {"
         ]
      ++ concat [["  case " <> tshow k <> ":"] ++ map (("    " <>) . assign) sets ++ ["    break;"] | (k, sets) <- zip [1 :: Int ..] (runCycles r), not (null sets)]
      ++ [ "  default: break;"
         , "  }"
         , "}"
         , "int main(void) {"
         , "  volatile int k = 0;"
         , "  setvbuf(stdout, NULL, _IONBF, 0);"
         , "  signal(SIGFPE, on_signal);"
         , "  signal(SIGSEGV, on_signal);"
         , "  signal(SIGABRT, on_signal);"
         , "  signal(SIGALRM, on_signal);"
         , "  alarm(2);"
         , "  if (sigsetjmp(trap, 1) == 0) {"
         , "    for (k = 1; k <= " <> tshow (length (runCycles r)) <> "; k++) {"
         , "      before_cycle(k);"
         , "      virtual_ns = (int64_t)(k - 1) * " <> tshow (runCycleNs r) <> "LL;"
         ]
      ++ ["      " <> n <> "(" <> n <> "_instance);" | n <- runPrograms r]
      ++ [ "    }"
         , "  } else {"
         , "    signal(SIGFPE, SIG_DFL); signal(SIGSEGV, SIG_DFL); signal(SIGABRT, SIG_DFL);"
         , "    alarm(0);"
         , "    printf(\"trap %d %d\\n\", (int)caught, (int)k);"
         , "  }"
         ]
      ++ map (("  " <>) . printOne) (runObserved r)
      ++ [ "  printf(\"end\\n\");"
         , "  return 0;"
         , "}"
         ]
  where
    probes = foldl' (\acc i -> if i `elem` acc then acc else acc ++ [i]) [] ([i | (_, i, _) <- runObserved r] ++ [i | c <- runCycles r, (i, _, _) <- c])
    at i ct = "AT(__stref_p" <> tshow i <> "(), " <> ct <> ")"
    printOne (_, i, t) = case t of
      TArray bs et | Right ct <- leafType "" et ->
        "for (int j = 0; j < " <> tshow (product [hi - lo + 1 | (lo, hi) <- bs]) <> "; j++) { " <> printLeaf et ("(" <> at i ct <> " + j)") <> " }"
      _ -> printLeaf t (at i (either (const "char") id (leafType "" t)))
    printLeaf t ptr = case t of
      TString _ n -> "put_string((const char *)" <> ptr <> ", " <> tshow n <> ");"
      TElem REAL -> "put_real(*" <> ptr <> ");"
      TElem LREAL -> "put_lreal(*" <> ptr <> ");"
      _ -> case leafType "" t of
        Right ct
          | "uint" `T.isPrefixOf` ct -> "printf(\"= %llu\\n\", (unsigned long long)*" <> ptr <> ");"
          | otherwise -> "printf(\"= %lld\\n\", (long long)*" <> ptr <> ");"
        Left _ -> "printf(\"= ?\\n\");"
    assign (i, t, v) = case (t, v) of
      (TString _ n, VString s) ->
        "memcpy(" <> at i "char" <> ", \"" <> T.concat [T.pack ('\\' : octal (ord c)) | c <- T.unpack (T.take n s)] <> "\", " <> tshow (min n (T.length s)) <> "); "
          <> at i "char" <> "[" <> tshow (min n (T.length s)) <> "] = 0;"
      (_, VBool b) -> "*" <> at i "uint8_t" <> " = " <> (if b then "1" else "0") <> ";"
      (_, VReal f) -> "{ uint32_t u = 0x" <> T.pack (showHex (castFloatToWord32 f) "") <> "UL; memcpy(" <> at i "float" <> ", &u, 4); }"
      (_, VLReal d) -> "{ uint64_t u = 0x" <> T.pack (showHex (castDoubleToWord64 d) "") <> "ULL; memcpy(" <> at i "double" <> ", &u, 8); }"
      (_, VTime TIME ms) -> "*" <> at i "int64_t" <> " = " <> tshow (ms * 1000000) <> "LL;"
      (_, VTime _ ns) -> "*" <> at i "int64_t" <> " = " <> tshow ns <> "LL;"
      (_, VDate ms) -> "*" <> at i "int64_t" <> " = " <> tshow (ms * 1000000) <> "LL;"
      (_, VTod ms) -> "*" <> at i "int64_t" <> " = " <> tshow (ms * 1000000) <> "LL;"
      (_, VDT ms) -> "*" <> at i "int64_t" <> " = " <> tshow (ms * 1000000) <> "LL;"
      (TEnum _ vs, VEnum _ x) -> "*" <> at i "int32_t" <> " = " <> maybe "0" tshow (elemIndex x vs) <> ";"
      (_, VInt _ n) -> case leafType "" t of
        Right ct -> "*" <> at i ct <> " = (" <> ct <> ")" <> (if n < 0 then "(" <> tshow n <> "LL)" else tshow n <> "ULL") <> ";"
        Left _ -> ""
      _ -> ""
    octal c = [toEnum (48 + (c `shiftR` 6) .&. 7), toEnum (48 + (c `shiftR` 3) .&. 7), toEnum (48 + c .&. 7)]

------------------------------------------------------------------------------
-- Answers

-- | plc did not compile the program: its first error. With
-- @--error-format clang@ it writes @file:LINE:COL:{range}: error[E0NN]:
-- message@; some of its checks write @message at: file:LINE:COL:...@ with
-- the line counted from 0. An error in the probes means a path the driver
-- cannot reach. Nothing else located: its code generator failed, the
-- message says how.
compileAnswer :: Int -> Text -> Answer
compileAnswer status err
  | status > 128 || status < 0 = AnswerRejected Nothing Nothing ("plc stopped with signal " <> tshow (if status > 128 then status - 128 else negate status) <> " (it crashed) while compiling the program")
  | otherwise = case mapMaybe located (T.lines err) ++ mapMaybe locatedAt (T.lines err) of
      (file, l, m) : _
        | file == probeFile -> AnswerUnsupported ("a variable the case observes is one plc does not let the driver reach: " <> m)
        | file == caseFile -> AnswerRejected (Just l) Nothing m
        | otherwise -> AnswerRejected Nothing Nothing (file <> ":" <> tshow l <> ": " <> m)
      [] -> AnswerRejected Nothing Nothing (T.strip (T.take 500 (T.unlines [l | l <- T.lines err, not (": warning[" `T.isInfixOf` l)])))
  where
    located ln = case T.breakOn ": error[" ln of
      (loc, rest) | not (T.null rest) ->
        case T.splitOn ":" loc of
          file : line : _ | Right (n, "") <- TR.decimal line -> Just (T.takeWhileEnd (/= '/') file, n, T.strip (T.drop 2 (T.dropWhile (/= ']') rest)))
          _ -> Nothing
      _ -> Nothing
    locatedAt ln = case T.breakOn " at: " ln of
      (msg, rest) | not (T.null rest) ->
        case T.splitOn ":" (T.drop 5 rest) of
          file : line : _ | Right (n, "") <- TR.decimal line -> Just (T.takeWhileEnd (/= '/') file, n + 1, T.strip msg)
          _ -> Nothing
      _ -> Nothing

-- | The answer from the driver's output.
runAnswer :: Run -> RunOutcome -> Answer
runAnswer r = driverAnswer (\raws -> M.fromList (fst (foldl' decodeOne ([], raws) (runObserved r))))
  where
    decodeOne (acc, raws) (path, _, t) =
      let n = case t of
            TArray bs _ -> fromInteger (product [hi - lo + 1 | (lo, hi) <- bs])
            _ -> 1
          (mine, rest) = splitAt n raws
       in case decodeRaw t mine of
            Just (v, []) -> ((path, valueScalar v) : acc, rest)
            _ -> (acc, rest)

tshow :: Show a => a -> Text
tshow = T.pack . show
