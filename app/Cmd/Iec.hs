-- | The commands for the dialects that run the IEC model (@--dialect
-- tecomat@): check a compilation unit, run its programs over scan cycles,
-- evaluate a snippet as the body of a program.
module Cmd.Iec
  ( dialectPolicies
  , isIecDialect
  , checkIec
  , parseIec
  , runIec
  , defaultCycle
  , evalIec
  , evalIecRows
  , evalIecTrace
  , oneStatementALine
  , RunIecOptions (..)
  , compareIec
  ) where

import Control.Monad (foldM, forM_, unless, when)
import Data.Aeson ((.=))
import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.Char (isAlpha, isAlphaNum, toUpper)
import Data.List (sortOn)
import Data.Maybe (fromMaybe)
import Data.Scientific (floatingOrInteger)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import System.Exit
import System.IO (stderr)
import Stref.Conformance.Protocol (Scalar (..))
import Stref.Values (realFromBits)
import Numeric (showHex)
import Stref.IEC.Check (ProgramChoice (..), checkUnit, locationType)
import Stref.IEC.Checked
import Stref.IEC.Engine
import Stref.IEC.Eval (Machine (..), Stop (..), readLocatedVar, readVariablePath, traceOf)
import Stref.IEC.Parser (parseUnit)
import Stref.IEC.Syntax
import Stref.IEC.Types (Elem (TIME))
import Stref.IEC.Values
import Stref.Policy
import Stref.IEC.Portability (portability)
import Stref.Portability (renderWarning, warningJson)
import Stref.Trace (Item, items, renderJsonLines, renderText, watching)
import Stref.Verification (renderError)
import Cmd.Common (Comparison (..), inSnippet, portabilitySummary, printComparison, rejectionJson, sourceLine)

-- | The preset of a dialect with @--policy K=V@ assignments applied.
dialectPolicies :: String -> [String] -> Either Text Policies
dialectPolicies dialect assignments = do
  preset <- maybe (Left ("unknown dialect '" <> T.pack dialect <> "'; the dialects are: " <> T.intercalate ", " (map fst presets))) Right (lookupPreset (T.pack dialect))
  foldM assign preset assignments
  where
    assign p kv = case T.breakOn "=" (T.pack kv) of
      (k, v) | not (T.null v) -> setPolicy k (T.drop 1 v) p
      _ -> Left ("--policy takes K=V, not '" <> T.pack kv <> "'")

isIecDialect :: Policies -> Bool
isIecDialect p = pModel p == IecController

-- | @stref parse --dialect tecomat FILE@: the unit's declarations, or its
-- syntax tree with @--ast@.
parseIec :: Policies -> FilePath -> Text -> Bool -> IO ExitCode
parseIec pol file src ast = case parseUnit pol file src of
  Left e -> do
    TIO.hPutStr stderr (renderError file src e)
    pure (ExitFailure 1)
  Right unit@(Unit decls)
    | ast -> print unit >> pure ExitSuccess
    | otherwise -> do
        forM_ decls $ \case
          DTypes ts -> forM_ ts $ \t -> TIO.putStrLn ("TYPE " <> tdName t)
          DGlobals b -> TIO.putStrLn ("VAR_GLOBAL " <> T.intercalate ", " (concatMap (map snd . vdNames) (vbDecls b)))
          DPou p -> TIO.putStrLn (kindWord (pouKind p) <> " " <> pouName p <> " (" <> T.pack (show (length (pouBody p))) <> " statements)")
          DVarConfig es -> TIO.putStrLn ("VAR_CONFIG " <> T.intercalate ", " [T.intercalate "." (cfgEntryPath e) | e <- es])
          DConfig c -> TIO.putStrLn ("CONFIGURATION " <> cfgName c <> ": " <> T.intercalate ", " [pcInstance pc <> " : " <> pcType pc | r <- cfgResources c, pc <- resPrograms r])
        pure ExitSuccess
  where
    kindWord = pouKindKeyword

-- | @stref check --dialect tecomat FILE@: parse and check the unit.
-- With @--portability@, the constructs whose meaning a policy decides are
-- listed after it (warnings: the exit status stays 0); @json@ prints one
-- JSON object instead.
checkIec :: Policies -> FilePath -> Text -> Bool -> Bool -> IO ExitCode
checkIec pol file src portable json = case parseUnit pol file src >>= checkUnit pol AllPrograms of
  Left e
    | json -> BL.putStrLn (A.encode (rejectionJson file [e])) >> pure (ExitFailure 1)
    | otherwise -> do
        TIO.hPutStr stderr (renderError file src e)
        pure (ExitFailure 1)
  Right prog -> do
    let pous = M.elems (prPous prog)
        user = [d | d <- pous, isUser d]
        warnings = if portable then portability pol prog else []
    if json
      then BL.putStrLn (A.encode (A.object (["file" .= file, "valid" .= True, "errors" .= ([] :: [A.Value])] ++ ["warnings" .= map (warningJson pol) warnings | portable])))
      else do
        putStrLn (file <> ": valid (" <> show (length user) <> " POUs: " <> T.unpack (T.intercalate ", " [kindText (pdKind d) <> " " <> pdName d | d <- sortOn (posOf . pdEndPos) user]) <> ")")
        mapM_ (TIO.putStrLn . renderWarning pol file) warnings
        when portable $ putStrLn (portabilitySummary (length warnings))
    pure ExitSuccess
  where
    isUser d = case pdBody d of
      Statements _ -> True
      Native _ -> False
    posOf (Pos l c) = (l, c)
    kindText = pouKindKeyword

data RunIecOptions = RunIecOptions
  { riCalls :: Int
  , riCycle :: Text
  , riProgram :: Maybe Text
  , riSets :: [(Text, Text)] -- ^ path, ST literal or number, written before the first cycle
  , riJson :: Bool
  , riTrace :: Maybe (Bool, [Text])
  -- ^ @--trace@: whether every loop iteration is kept (@--trace-all@), and
  -- the @--watch@ names
  , riWatch :: [Text] -- ^ @--watch@ without @--trace@: a table, a row per cycle
  , riScenario :: Maybe [Call] -- ^ @--scenario FILE@: the cycles, instead of @--calls@
  , riSnippet :: Maybe Text -- ^ @stref eval@: the snippet the source wraps, where errors are shown
  , riEvaluator :: Evaluator -- ^ @--readable@: every cycle in the readable evaluator
  }

-- | @stref run --dialect tecomat FILE@: the programs over N cycles on the
-- virtual clock; the variables of every program instance and the globals
-- after the last cycle.
runIec :: Policies -> FilePath -> Text -> RunIecOptions -> IO ExitCode
runIec pol file src o = case cycleMillis pol (riCycle o) of
  Left e -> usage e
  Right cycle -> do
    let choice = maybe ProgramsOfConfiguration ProgramNamed (riProgram o)
        sets = [(p, toScalar v) | (p, v) <- riSets o]
        calls = case riScenario o of
          -- --set writes before the first cycle of a scenario too
          Just (Scan first : rest) -> Scan (sets ++ first) : rest
          Just scenario -> scenario
          Nothing -> if riCalls o <= 0 then [] else Scan sets : replicate (riCalls o - 1) (Scan [])
        observer = if null (riWatch o) then Nothing else Just (\prog m -> map (watchValue pol prog m) (riWatch o))
    case runProgramWith (riEvaluator o) observer (fst <$> riTrace o) pol file src choice cycle [] calls of
      Left e0
        | riJson o -> BL.putStrLn (A.encode (rejectionJson file [e])) >> pure (ExitFailure 1)
        | otherwise -> do
            TIO.hPutStr stderr (renderError file (fromMaybe src (riSnippet o)) e)
            pure (ExitFailure 1)
        where
          e = maybe e0 (\sn -> inSnippet src sn e0) (riSnippet o)
      Right (Left e) -> usage e
      Right (Right (_, (_, row) : _)) | Just bad <- lookup Nothing (zip row (riWatch o)) ->
        usage ("--watch " <> bad <> ": no variable of that name (give a path such as MAIN.x, a global, or a direct address such as %QX0.0)")
      Right (Right (r, rows)) -> do
        let vars = observedVariables r
            err = rrError r
        forM_ (riTrace o) $ \(_, watch) ->
          mapM_ TIO.putStrLn $
            (if riJson o then renderJsonLines pol else renderText pol (sourceLine src)) (watching watch (items (traceOf (rrMachine r))))
        let errorIn k = case err of
              Just (k', StopFault (Pos l _) f) | k' == k -> Just (faultKind f <> " at line " <> T.pack (show l))
              _ -> Nothing
            clockAt k = (toInteger k - 1) * cycle
        unless (null (riWatch o)) $
          if riJson o
            then forM_ rows $ \(k, vs) ->
              BL.putStrLn (A.encode (A.object (["cycle" .= k, "clock_ms" .= clockAt k, "vars" .= A.object [K.fromText n .= v | (n, Just v) <- zip (riWatch o) vs]] ++ ["error" .= e | Just e <- [errorIn k]])))
            else
              mapM_ TIO.putStrLn $
                table
                  (["cycle", "clock"] ++ riWatch o ++ ["error" | err /= Nothing])
                  [[T.pack (show k), renderTime TIME (clockAt k)] ++ map (maybe "?" scalarText) vs ++ [fromMaybe "" (errorIn k) | err /= Nothing] | (k, vs) <- rows]
        if riJson o
          then
            BL.putStrLn $
              A.encode $
                A.object
                  [ "cycles" .= rrCycles r
                  , "clock_ms" .= mClock (rrMachine r)
                  , "error" .= fmap (\(k, StopFault (Pos l _) f) -> A.object ["cycle" .= k, "kind" .= faultKind f, "line" .= l, "message" .= faultMessage f]) err
                  , "vars" .= A.object [K.fromText n .= v | (n, v) <- vars]
                  ]
          else do
            putStrLn ("cycles run: " <> show (rrCycles r) <> " (cycle " <> T.unpack (riCycle o) <> ", clock at the last cycle " <> T.unpack (renderTime TIME (mClock (rrMachine r))) <> ")")
            case err of
              Nothing -> putStrLn "error: none"
              Just (k, StopFault (Pos l _) f) -> putStrLn ("error: " <> T.unpack (faultKind f) <> " in cycle " <> show k <> " at line " <> show l <> ": " <> T.unpack (faultMessage f))
            -- a watch table shows what was asked for; without one, every variable
            when (null (riWatch o)) $ forM_ vars $ \(n, v) -> TIO.putStrLn ("  " <> n <> " = " <> scalarText v)
        pure (maybe ExitSuccess (const (ExitFailure 1)) err)
  where
    usage e = TIO.hPutStrLn stderr ("stref run: " <> e) >> pure (ExitFailure 2)

-- | @stref run FILE --presets A B ...@ or @--compare POLICY@: the program
-- under each variant over the same cycles, side by side, the variables that
-- differ marked, and the first cycle after which they part (found by
-- running 1, 2, ... cycles, up to 1000).
compareIec :: [(Text, Policies)] -> FilePath -> Text -> RunIecOptions -> IO ExitCode
compareIec variants file src o = case mapM (\(_, p) -> cycleMillis p (riCycle o)) variants of
  Left e -> usage e
  Right cycles -> do
    let choice = maybe ProgramsOfConfiguration ProgramNamed (riProgram o)
        sets = [(p, toScalar v) | (p, v) <- riSets o]
        callsFor n = if n <= 0 then [] else Scan sets : replicate (n - 1) (Scan [])
        outcome n (p, cyc) = case runProgram p file src choice cyc [] (callsFor n) of
          Left e -> Left (renderError file src e)
          Right (Left e) -> Left e
          Right (Right r) -> Right (M.fromList (observedVariables r), (\(k, StopFault (Pos l _) f) -> (k, faultKind f, l)) <$> rrError r)
        atCycles n = [outcome n (p, c) | ((_, p), c) <- zip variants cycles]
        final = atCycles (riCalls o)
        parted n = let xs = atCycles n in any (/= head xs) xs
        -- the first cycle after which the variants' variables or errors
        -- differ, also when they agree again by the last cycle
        firstParting = case filter parted [1 .. min 1000 (riCalls o)] of
          k : _ -> Just k
          [] -> Nothing
        paths = M.keys (M.unions [m | Right (m, _) <- final])
        valueOf r path = either (const "rejected") (\(m, _) -> maybe "-" scalarText (M.lookup path m)) r
        errorText = \case
          Left e -> "rejected: " <> T.strip (head (T.lines e <> [""]))
          Right (_, Nothing) -> "none"
          Right (_, Just (k, kind, l)) -> kind <> " in cycle " <> T.pack (show k) <> " at line " <> T.pack (show l)
    printComparison (riJson o) $
      Comparison (map fst variants) "cycle" (riCalls o) firstParting (map errorText final) [(path, map (`valueOf` path) final) | path <- paths]
  where
    usage e = TIO.hPutStrLn stderr ("stref run: " <> e) >> pure (ExitFailure 2)

-- | A watched name's value after a cycle: a path (@MAIN.x@, @MAIN.fb.Q@,
-- @MAIN.a[2]@), a global, a variable of the only program instance named
-- without its instance, or a direct address; Nothing when it names none.
watchValue :: Policies -> Program -> Machine -> Text -> Maybe Scalar
watchValue pol prog m name
  | "%" `T.isPrefixOf` name = case locationOf pol name of
      Right l -> Just (programScalar prog (readLocatedVar prog l (locationType l) m))
      Left _ -> Nothing
  | otherwise = case [v | p <- name : [inst <> "." <> name | (inst, _) <- prRoots prog], Right steps <- [parseVarPath p], Just (v, _) <- [readVariablePath prog m steps]] of
      v : _ -> Just (programScalar prog v)
      [] -> Nothing

-- | Rows under a header, in columns as wide as their widest cell.
table :: [Text] -> [[Text]] -> [Text]
table header rows = map line (header : rows)
  where
    widths = [maximum (map T.length col) | col <- transposed (header : rows)]
    transposed xs = if any null xs then [] else map head xs : transposed (map tail xs)
    line cells = T.stripEnd (T.intercalate "  " [T.justifyLeft w ' ' c | (w, c) <- zip widths cells])

toScalar :: Text -> Scalar
toScalar v = case reads (T.unpack v) :: [(Integer, String)] of
  [(n, "")] -> SNumber (fromInteger n)
  _ -> case T.toUpper v of
    "TRUE" -> SBool True
    "FALSE" -> SBool False
    _ -> case reads (T.unpack v) :: [(Double, String)] of
      [(_, "")] -> SNumber (read (T.unpack v))
      _ -> SText v

-- | Every variable of the program instances and the globals, flattened to
-- paths (structures, arrays and FB instances element by element).
observedVariables :: RunResult -> [(Text, Scalar)]
observedVariables r =
  let m = rrMachine r
      prog = rrProgram r
      globals = [(viName v, v) | v <- prGlobals prog]
      instances = [(inst, t) | (inst, t) <- prRoots prog]
      -- arrays by their own indices (ARRAY [0..4] from a[0]), structures and
      -- instances field by field
      pathsOf prefix = \case
        VArray bs xs -> concat [pathsOf (prefix <> "[" <> T.intercalate "," (map (T.pack . show) ix) <> "]") v | (ix, v) <- zip (sequence [[lo .. hi] | (lo, hi) <- bs]) (foldr (:) [] xs)]
        VStruct fs -> concat [pathsOf (prefix <> "." <> k) x | (k, x) <- M.toList fs]
        VInstance _ fs -> concat [pathsOf (prefix <> "." <> k) x | (k, x) <- M.toList fs, not ("$" `T.isInfixOf` k)]
        v -> [(prefix, programScalar prog v)]
      observe p = case parseVarPath p of
        Right steps -> maybe [] (\(v, _) -> pathsOf p v) (readVariablePath prog m steps)
        Left _ -> []
   in concatMap (\(n, _) -> observe n) globals
        ++ concat [observe (inst <> "." <> viName v) | (inst, t) <- instances, Just d <- [lookupPou prog t], v <- pdVars d, not (T.null (viName v))]

scalarText :: Scalar -> Text
scalarText = \case
  SNumber n -> case floatingOrInteger n :: Either Double Integer of
    Right i -> T.pack (show i)
    Left d -> T.pack (show d)
  SBool b -> if b then "TRUE" else "FALSE"
  SText t -> t
  SNaN -> "NaN"
  -- a REAL infinity, -0.0 or NaN with a payload, as its value and pattern
  SBits w -> T.pack (show (realFromBits w)) <> " (16#" <> T.toUpper (T.pack (showHex w "")) <> ")"
  SList xs -> "[" <> T.intercalate ", " (map scalarText xs) <> "]"
  SMap fs -> "(" <> T.intercalate ", " [k <> " := " <> scalarText v | (k, v) <- M.toList fs] <> ")"

-- | @stref eval --dialect tecomat SNIPPET@: VAR blocks and statements as
-- the body of a PROGRAM, run for N cycles.
evalIec :: Policies -> Text -> Int -> Maybe (Bool, [Text]) -> IO ExitCode
evalIec pol snippet calls traced = do
  let written = maybe snippet (const (oneStatementALine snippet)) traced
  runIec pol "<snippet>" (snippetProgram written) (RunIecOptions calls "T#10ms" Nothing [] False traced [] Nothing (Just written) FastWhereItApplies)

-- | A snippet as the body of PROGRAM MAIN (its line 1 is the program's 2).
snippetProgram :: Text -> Text
snippetProgram snippet = "PROGRAM MAIN\n" <> snippet <> "\nEND_PROGRAM\n"

-- | A one-line snippet with a line break after each semicolon, END_VAR,
-- DO, THEN, ELSE and REPEAT outside strings and comments, so that a trace shows one
-- statement a line.
oneStatementALine :: Text -> Text
oneStatementALine = T.strip . T.pack . go . T.unpack
  where
    go = \case
      [] -> []
      '\'' : rest -> quoted '\'' rest
      '"' : rest -> quoted '"' rest
      '(' : '*' : rest -> let (c, rest') = breakOn "*)" rest in "(*" <> c <> go rest'
      '/' : '/' : rest -> let (c, rest') = break (== '\n') rest in "//" <> c <> go rest'
      ';' : rest -> ";\n" <> go (dropWhile (== ' ') rest)
      c : rest
        | isAlpha c || c == '_' ->
            let (word, rest') = span (\x -> isAlphaNum x || x == '_') (c : rest)
             in if map toUpper word `elem` ["END_VAR", "DO", "THEN", "ELSE", "REPEAT"]
                  then word <> "\n" <> go (dropWhile (== ' ') rest')
                  else word <> go rest'
        | otherwise -> c : go rest
    quoted q rest = let (str, rest') = break (== q) rest in q : str <> take 1 rest' <> go (drop 1 rest')
    breakOn end xs = case xs of
      [] -> ([], [])
      _ | take 2 xs == end -> (end, drop 2 xs)
      x : more -> let (a, b) = breakOn end more in (x : a, b)

-- | The program a snippet makes and the items of its trace over N cycles;
-- Nothing when rejected.
evalIecTrace :: Policies -> Text -> Int -> Maybe (Text, [Item])
evalIecTrace pol snippet calls =
  let src = snippetProgram (oneStatementALine snippet)
   in case runProgramTraced (Just False) pol "<snippet>" src ProgramsOfConfiguration 10 [] (replicate (max 1 calls) (Scan [])) of
        Right (Right r) -> Just (src, items (traceOf (rrMachine r)))
        _ -> Nothing

-- | The rows a snippet leaves (every variable, then the error), for
-- @stref eval --dialect tecomat --compare POLICY@; Nothing when rejected.
evalIecRows :: Policies -> Text -> Int -> Maybe [(Text, Text)]
evalIecRows pol snippet calls =
  let src = "PROGRAM MAIN\n" <> snippet <> "\nEND_PROGRAM\n"
   in case runProgram pol "<snippet>" src ProgramsOfConfiguration 10 [] (replicate (max 1 calls) (Scan [])) of
        Right (Right r) ->
          Just
            ( [(n, scalarText v) | (n, v) <- observedVariables r]
                ++ [("error", maybe "none" (\(k, StopFault (Pos l _) f) -> faultKind f <> " in cycle " <> T.pack (show k) <> " at line " <> T.pack (show (l - 1))) (rrError r))]
            )
        _ -> Nothing

-- | The cycle of a run that gives none: the greatest common divisor of the
-- configuration's task intervals, so that every task comes round on the
-- virtual clock (docs/tecomat.md, tasks), else T#10ms.
defaultCycle :: Policies -> FilePath -> Text -> Maybe Text -> Text
defaultCycle pol file src program =
  case parseUnit pol file src >>= checkUnit pol (maybe ProgramsOfConfiguration ProgramNamed program) of
    Right prog | periods@(_ : _) <- filter (> 0) (M.elems (prPeriods prog)) -> "T#" <> T.pack (show (foldr1 gcd periods)) <> "ms"
    _ -> "T#10ms"
