-- | @stref explore@: property-based exploration of the semantics.
--
-- * @--engine CMD@: generate well-typed programs, run each on the reference
--   and on the engine through the @stref-engine/1@ protocol; shrink every
--   disagreement to a small program and (with @--out DIR@) write it as a
--   corpus case marked @features: [generated, unreviewed]@.
-- * @--compare POLICY@ (or @--presets A B@): find programs whose results
--   differ between the alternatives, and print the smallest one found.
--
-- Reproducible: the seed is printed, and @--seed@ replays the same programs.
module Cmd.Explore (command) where

import Control.Monad (foldM, forM, forM_, when)
import Data.IORef
import Data.List (nub, sortOn)
import qualified Data.Map.Strict as M
import Data.Maybe (fromMaybe, isJust)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative as O
import System.Directory (createDirectoryIfMissing)
import System.Exit
import System.FilePath (takeFileName, (</>))
import System.IO (hFlush, hPutStrLn, stderr, stdout)
import Stref.Checked (ArithOp (..))
import Cmd.Common (engineCommand)
import Cmd.ExploreIec (ExploreIec (..), IecMode (..), exploreIec)
import Cmd.Iec (dialectPolicies, isIecDialect)
import Stref.Conformance.Corpus (readListFile)
import Stref.Conformance.Runner (EngineSpec (..), RunOptions (..), askEngine, defaultRunOptions)
import Stref.Generate.Iec (keepsAType, knownFeatures, supportUnder, withoutFeatures)
import Stref.Engine (referenceEngine)
import Stref.Explore.Run
import Stref.Generate.Program
import Stref.Operands (renderOperand)
import Stref.Policy
import Stref.Types (BasicType (..))
import Stref.Values
import Test.QuickCheck (choose, generate)

data Mode
  = AgainstEngine String
  | ComparePolicy String
  | ComparePresets String String
  | PrintPrograms

data Options = Options
  { optMode :: Mode
  , optCount :: Int
  , optSeed :: Maybe Int
  , optSize :: Int
  , optOut :: Maybe FilePath
  , optPolicies :: [String]
  , optShrinkBudget :: Int
  , optTimeout :: Double
  , optCalls :: Maybe Int
  , optDialect :: String
  , optExcluded :: [Text]
  , optFeaturesFile :: Maybe FilePath
  }

command :: Mod CommandFields (IO ExitCode)
command =
  O.command "explore" $
    info
      (run <$> options)
      ( progDesc
          "Generate well-typed programs and look for disagreements: between the reference and an engine (--engine), \
          \or between the alternatives of a policy (--compare) or two presets (--presets). Exit 1 when one is found."
      )

options :: Parser Options
options =
  Options
    <$> mode
    <*> option auto (long "count" <> metavar "N" <> value 100 <> showDefault <> help "How many programs to generate")
    <*> optional (option auto (long "seed" <> metavar "S" <> help "Seed of the first program (printed by every run; replays it)"))
    <*> option auto (long "size" <> metavar "Z" <> value 30 <> showDefault <> help "QuickCheck size of the programs")
    <*> optional (strOption (long "out" <> metavar "DIR" <> help "Write each shrunk disagreement as a corpus case into DIR"))
    <*> many (strOption (long "policy" <> metavar "K=V" <> help "A policy of the reference (default: the mastertool-xe preset)"))
    <*> option auto (long "shrink-budget" <> metavar "N" <> value 400 <> showDefault <> help "At most N runs while shrinking one disagreement")
    <*> option auto (long "timeout" <> metavar "SECONDS" <> value 10 <> showDefault <> help "Time limit of one engine run")
    <*> optional (option auto (long "calls" <> metavar "N" <> help "Module calls per program (default 1; 2 for --compare lifetime)"))
    <*> strOption (long "dialect" <> metavar "NAME" <> value "mastertool-xe" <> showDefault <> help "The dialect of the generated programs: mastertool-xe, or an IEC dialect (tecomat, nexto: IEC programs with FB instances, TIME, bit strings, over 1-4 cycles)")
    <*> many (strOption (long "exclude-feature" <> metavar "F" <> help "IEC dialects: a corpus feature the engine lacks (a type, if, case, for, timers, conversions, ...); the programs do without it (repeatable)"))
    <*> optional (strOption (long "features-file" <> metavar "FILE" <> help "IEC dialects: the features the engine lacks, one a line (# comments), the file conformance --features-file reads; names the programs never use are ignored"))
  where
    mode =
      (AgainstEngine <$> strOption (long "engine" <> metavar "CMD" <> help "The engine command (request on stdin, answer on stdout)"))
        <|> (ComparePolicy <$> strOption (long "compare" <> metavar "POLICY" <> help "Compare the alternatives of a policy, e.g. name-resolution"))
        <|> ( ComparePresets
                <$> strOption (long "presets" <> metavar "A" <> help "Compare two presets: --presets A B")
                <*> strArgument (metavar "B" <> help "The second preset of --presets")
            )
        <|> flag' PrintPrograms (long "print" <> help "Only print the generated programs and the reference's results")

usage :: Text -> IO ExitCode
usage msg = hPutStrLn stderr ("stref explore: " <> T.unpack msg) >> pure (ExitFailure 2)

-- | Explorations run with a small step budget, so that a loop that never
-- ends under some alternative ends quickly in error 2030.
explorationBudget :: Int
explorationBudget = 200000

run :: Options -> IO ExitCode
run o = case dialectPolicies (optDialect o) (optPolicies o) of
  Left msg -> usage msg
  Right pol | isIecDialect pol -> do
    declared <- maybe (pure (Right [])) (readListFile "features") (optFeaturesFile o)
    lacking <- either (\e -> usage e >>= exitWith) pure declared
    case [f | f <- optExcluded o, f `notElem` knownFeatures] of
      [] -> pure ()
      unknown ->
        usage ("--exclude-feature " <> T.intercalate ", " unknown <> ": the generated programs never use it; the features they can do without: " <> T.intercalate ", " knownFeatures)
          >>= exitWith
    -- the requests name the IEC dialect given, tecomat for an engine's preset
    let requestDialect = if optDialect o `elem` ["tecomat", "nexto"] then T.pack (optDialect o) else "tecomat"
    -- the language of the policies in force, as they spell it
    let base = supportUnder pol
        support = withoutFeatures (optExcluded o ++ lacking) base
    when (not (keepsAType support)) $
      usage "the excluded features leave no type to generate programs with" >>= exitWith
    seed <- maybe (generate (choose (0, 999999))) pure (optSeed o)
    engine <- case optMode o of
      AgainstEngine cmd -> engineCommand cmd
      _ -> pure (Right "")
    either (\why -> usage why >>= exitWith) (const (pure ())) engine
    let mode = case optMode o of
          AgainstEngine _ -> Just (IecEngine (either (const "") id engine))
          ComparePolicy name -> Just (IecCompare (T.pack name))
          PrintPrograms -> Just IecPrint
          ComparePresets {} -> Nothing
    case mode of
      Nothing -> usage "--presets compares MasterTool XE presets; for tecomat use --compare POLICY"
      Just m -> exploreIec pol {pStepBudget = min (pStepBudget pol) explorationBudget} (ExploreIec m requestDialect support (optCount o) seed (optSize o) (optShrinkBudget o) (optTimeout o))
  Right _
    | not (null (optExcluded o)) || isJust (optFeaturesFile o) ->
        usage "--exclude-feature and --features-file restrict the IEC dialects' programs (--dialect tecomat, nexto); the MasterTool XE programs have a fixed shape"
    | otherwise -> runMasterTool o

runMasterTool :: Options -> IO ExitCode
runMasterTool o = case foldM (\p kv -> let (k, v) = T.breakOn "=" (T.pack kv) in setPolicy k (T.drop 1 v) p) mastertoolXE (optPolicies o) of
  Left msg -> usage msg
  Right reference0 -> do
    let reference = reference0 {pStepBudget = min (pStepBudget reference0) explorationBudget}
    seed <- maybe (generate (choose (0, 999999))) pure (optSeed o)
    let announce = putStrLn ("seed " <> show seed <> " (replay with --seed " <> show seed <> " --count " <> show (optCount o) <> " --size " <> show (optSize o) <> ")")
    case optMode o of
      AgainstEngine cmd -> announce >> againstEngine o reference seed cmd
      ComparePolicy name -> case alternativesOf (T.pack name) reference of
        Left msg -> usage msg
        Right alts -> announce >> compareAlternatives o seed (configFor name) alts
      PrintPrograms -> do
        announce
        forM_ (programs o defaultGenConfig seed) $ \(s, gm) -> do
          putStrLn ("(* program " <> show s <> " *)")
          TIO.putStr (generatedSource gm)
          let answer = referenceEngine [] (explorationRequest reference (fromMaybe 1 (optCalls o)) "explore" gm)
          mapM_ (TIO.putStrLn . ("(* " <>) . (<> " *)")) (renderSummary gm (summarise gm (Right answer)))
        pure ExitSuccess
      ComparePresets a b -> case (lookupPreset (T.pack a), lookupPreset (T.pack b)) of
        (Just pa, Just pb) -> announce >> compareAlternatives o seed defaultGenConfig [(T.pack a, budgeted pa), (T.pack b, budgeted pb)]
        _ -> usage ("unknown preset; the presets are: " <> T.intercalate ", " (map fst presets))
  where
    budgeted p = p {pStepBudget = explorationBudget}
    -- Programs that can show the policy at all.
    configFor name = case name of
      "name-resolution" -> defaultGenConfig {gcShadowing = True}
      "for-at-type-max" -> defaultGenConfig {gcTypeMaxFor = True}
      "for-bounds" -> defaultGenConfig {gcVariableForBounds = True}
      _ -> defaultGenConfig

programs :: Options -> GenConfig -> Int -> [(Int, GenModule)]
programs o cfg seed = [(s, generateWithSeed s (optSize o) (genModule cfg)) | s <- take (optCount o) [seed ..]]

-- | Greedy shrinking: take the first smaller candidate that still shows the
-- problem, until none does or the budget is spent.
shrinkWith :: Int -> (GenModule -> IO Bool) -> GenModule -> IO (GenModule, Int)
shrinkWith budget stillFails = go 0
  where
    go used gm = do
      found <- firstFailing used (shrinkGenModule gm)
      case found of
        (Just gm', used') -> go used' gm'
        (Nothing, used') -> pure (gm, used')
    firstFailing used = \case
      [] -> pure (Nothing, used)
      (c : cs)
        | used >= budget -> pure (Nothing, used)
        | otherwise -> do
            bad <- stillFails c
            if bad then pure (Just c, used + 1) else firstFailing (used + 1) cs

------------------------------------------------------------------------------
-- Against an engine

againstEngine :: Options -> Policies -> Int -> String -> IO ExitCode
againstEngine o reference seed cmd = do
  let ropts = defaultRunOptions {roEngine = External cmd, roTimeout = optTimeout o}
      ask gm = askEngine ropts (explorationRequest reference (fromMaybe 1 (optCalls o)) "explore" gm)
      refOf gm = summarise gm (Right (referenceEngine [] (explorationRequest reference (fromMaybe 1 (optCalls o)) "explore" gm)))
      -- an engine may decline a program (@unsupported@): counted, not a disagreement
      isUnsupported = \case
        SumUnsupported _ -> True
        _ -> False
      differs gm = do
        e <- summarise gm <$> ask gm
        pure (e /= refOf gm && not (isUnsupported e), e)
  found <- newIORef (0 :: Int)
  declined <- newIORef (0 :: Int)
  broken <- newIORef Nothing
  let isEngineError = \case
        SumEngineError _ -> True
        _ -> False
      -- a shrink step must keep a real disagreement, not an engine failure
      -- and a well-typed program: the reference must not reject it
      isRejected = \case
        SumRejected _ -> True
        _ -> False
      stillDiffers gm
        | isRejected (refOf gm) = pure False
        | otherwise = (\(bad, e) -> bad && not (isEngineError e)) <$> differs gm
  forM_ (programs o defaultGenConfig seed) $ \(s, gm) -> do
    stop <- readIORef broken
    when (stop == Nothing) $ do
      (bad, first) <- differs gm
      when (isUnsupported first) (modifyIORef declined (+ 1))
      if bad && isEngineError first
        then writeIORef broken (Just (s, first))
        else when bad $ do
          modifyIORef found (+ 1)
          putStrLn ("program " <> show s <> ": the engine disagrees with the reference; shrinking ...")
          hFlush stdout
          (small, used) <- shrinkWith (optShrinkBudget o) stillDiffers gm
          (_, engineSummary) <- differs small
          let refSummary = refOf small
          putStrLn ("shrunk in " <> show used <> " runs to:")
          TIO.putStr (generatedSource small)
          report small refSummary "engine" engineSummary
          forM_ (optOut o) $ \dir -> do
            createDirectoryIfMissing True dir
            let file = dir </> ("explore-" <> show s <> ".st")
            TIO.writeFile file (corpusCase (fromMaybe 1 (optCalls o)) s small refSummary (engineLabel cmd) engineSummary)
            putStrLn ("written " <> file)
  stop <- readIORef broken
  case stop of
    Just (s, SumEngineError msg) -> do
      hPutStrLn stderr ("stref explore: the engine failed on program " <> show s <> ": " <> T.unpack msg)
      pure (ExitFailure 2)
    _ -> finish found declined
  where
    finish found declined = do
      n <- readIORef found
      u <- readIORef declined
      putStrLn (show (optCount o) <> " programs, " <> show n <> " disagreement" <> (if n == 1 then "" else "s") <> (if u > 0 then ", " <> show u <> " unsupported by the engine" else ""))
      pure (if n == 0 then ExitSuccess else ExitFailure 1)

-- | The engine's command without directories (no machine paths in cases).
engineLabel :: String -> Text
engineLabel cmd = case words cmd of
  (exe : args) -> T.unwords (T.pack (takeFileName exe) : map T.pack args)
  [] -> ""

report :: GenModule -> Summary -> Text -> Summary -> IO ()
report gm refS otherName otherS = do
  printInputs gm
  putStrLn ("difference: " <> T.unpack (fromMaybe "-" (summaryDifference refS otherS)))
  putStrLn "reference:"
  mapM_ (TIO.putStrLn . ("  " <>)) (changedOnly gm refS otherS refS)
  putStrLn (T.unpack otherName <> ":")
  mapM_ (TIO.putStrLn . ("  " <>)) (changedOnly gm refS otherS otherS)

-- | The operand values before the call.
printInputs :: GenModule -> IO ()
printInputs gm =
  case gmInputs gm of
    [] -> pure ()
    ins -> TIO.putStrLn ("inputs: " <> T.intercalate ", " [renderOperand o <> " = " <> showInput v | (o, v) <- ins])
  where
    showInput = \case
      VBool b -> if b then "true" else "false"
      v -> showValue v

-- | The lines of a summary that differ from the other one (all of them when
-- the verdicts differ), so that a report shows only what matters.
changedOnly :: GenModule -> Summary -> Summary -> Summary -> [Text]
changedOnly gm a b s =
  let la = renderSummary gm a
      lb = renderSummary gm b
   in if length la == length lb
        then [l | (l, (x, y)) <- zip (renderSummary gm s) (zip la lb), x /= y || "error" `T.isPrefixOf` l]
        else renderSummary gm s

-- | A corpus case (conformance/README.md format): the reference's results as
-- the expectation, marked generated and unreviewed, both answers in a comment.
corpusCase :: Int -> Int -> GenModule -> Summary -> Text -> Summary -> Text
corpusCase calls s gm refS engineName engineS =
  T.unlines $
    [ "(*---"
    , "description: '" <> T.replace "'" "''" ("found by stref explore (seed " <> tshow s <> "); the reference and the engine (" <> engineName <> ") disagree on " <> fromMaybe "-" (summaryDifference refS engineS)) <> "'"
    , "rules: [" <> T.intercalate ", " (rulesOf gm) <> "]"
    , "features: [generated, unreviewed]"
    , "plc:"
    , "  init: {" <> T.intercalate ", " [quote (renderOperand op) <> ": " <> yamlValue v | (op, v) <- gmInputs gm] <> "}"
    ]
      ++ ["calls: " <> tshow calls | calls > 1]
      ++ ["expect:"]
      ++ expectation
      ++ ["---*)", "(* answers (both engines, before review):"]
      ++ map ("   reference: " <>) (renderSummary gm refS)
      ++ map ("   engine:    " <>) (renderSummary gm engineS)
      ++ ["*)"]
      ++ [generatedSource gm]
  where
    quote t = "\"" <> t <> "\""
    expectation = case refS of
      SumRun ops outs err _ ->
        [ "  operands: {" <> T.intercalate ", " [quote k <> ": " <> patternYaml k p | (k, Right p) <- ops] <> "}"
        , "  outputs: {" <> T.intercalate ", " [k <> ": " <> (if b then "true" else "false") | (k, Just b) <- outs] <> "}"
        , "  error: " <> maybe "none" (\c -> "{code: " <> tshow c <> "}") err
        ]
      SumRejected _ -> ["  verdict: rejected"]
      _ -> ["  verdict: ok"]
    types = M.fromList ([(renderOperand (mvOperand v), mvType v) | v <- gmMapped gm] ++ [(renderOperand o, gaType a) | a <- gmArrays gm, o <- arrayOperands a])
    patternYaml k w = case M.lookup k types of
      Just BOOL -> if w == 0 then "false" else "true"
      Just REAL -> "{bits: \"" <> hex w <> "\"}"
      _ -> tshow w
    yamlValue = \case
      VBool b -> if b then "true" else "false"
      VReal r -> "{bits: \"" <> hex (realBits r) <> "\"}"
      v -> maybe "0" tshow (valueToInteger v)
    hex w = let h = T.pack (showHex8 (toInteger w)) in "0x" <> T.justifyRight 8 '0' h
    showHex8 n = let digits = "0123456789ABCDEF" in if n < 16 then [digits !! fromInteger n] else showHex8 (n `div` 16) ++ [digits !! fromInteger (n `mod` 16)]

-- | The catalogue rules a generated program exercises.
rulesOf :: GenModule -> [Text]
rulesOf gm = nub ("MT-EXEC-9" : concatMap stmtRules (allStmts gm))
  where
    allStmts g = gpBody (gmProgram g) ++ concatMap gfBody (gmFunctions g)
    stmtRules = \case
      GAssign _ _ e -> "MT-STMT-2" : exprRules e
      GAssignIndex _ _ i e -> "MT-ARR-2" : exprRules i ++ exprRules e
      GCall _ as -> "MT-STMT-3" : concatMap exprRules as
      GIf arms els -> "MT-STMT-6" : concat [exprRules c ++ concatMap stmtRules b | (c, b) <- arms] ++ maybe [] (concatMap stmtRules) els
      GCase sel arms els -> "MT-STMT-8" : exprRules sel ++ concatMap (concatMap stmtRules . snd) arms ++ maybe [] (concatMap stmtRules) els
      GFor _ _ _ _ _ b -> "MT-STMT-18" : concatMap stmtRules b
      GForVar _ _ _ _ _ _ b -> "MT-STMT-19" : concatMap stmtRules b
      GWhile _ _ c b -> "MT-STMT-13" : exprRules c ++ concatMap stmtRules b
      GRepeat _ _ c b -> "MT-STMT-14" : exprRules c ++ concatMap stmtRules b
      GExit -> ["MT-STMT-12"]
      GReturn -> ["MT-STMT-5"]
      GEmpty -> []
    exprRules = \case
      TLit {} -> []
      TVar {} -> []
      TFlag -> ["MT-OP-7"]
      TWiden _ _ e -> "MT-CONV-6" : exprRules e
      TConv _ _ e -> "MT-CONV-5" : exprRules e
      TNeg _ e -> "MT-OP-6" : exprRules e
      TNot _ e -> "MT-OP-14" : exprRules e
      TArith op _ a b -> arithRule op : exprRules a ++ exprRules b
      TCmp _ _ a b -> "MT-OP-11" : exprRules a ++ exprRules b
      TLogic _ _ a b -> "MT-OP-12" : exprRules a ++ exprRules b
      TExpt _ a b -> "MT-OP-20" : exprRules a ++ exprRules b
      TCall _ _ as -> "MT-OP-18" : concatMap exprRules as
      TIndex _ _ i -> "MT-ARR-2" : exprRules i
    arithRule = \case
      OpDiv -> "MT-OP-9"
      OpMod -> "MT-OP-8"
      _ -> "MT-OP-6"

------------------------------------------------------------------------------
-- Between alternatives

compareAlternatives :: Options -> Int -> GenConfig -> [(Text, Policies)] -> IO ExitCode
compareAlternatives o seed cfg alts = do
  let calls = fromMaybe (if map fst alts == ["per-call", "retained"] then 2 else 1) (optCalls o)
  let summaries gm = [(name, summarise gm (Right (referenceEngine [] (explorationRequest p calls "explore" gm)))) | (name, p) <- alts]
      differs gm = case map snd (summaries gm) of
        (s : rest) -> any (/= s) rest
        [] -> False
      size gm = T.length (generatedSource gm)
  found <- fmap concat . forM (programs o cfg seed) $ \(s, gm) ->
    if differs gm
      then do
        (small, _) <- shrinkWith (optShrinkBudget o) (pure . differs) gm
        pure [(s, small)]
      else pure []
  putStrLn (show (optCount o) <> " programs, " <> show (length found) <> " show a difference between " <> T.unpack (T.intercalate " and " (map fst alts)))
  case sortOn (size . snd) found of
    [] -> pure ExitSuccess
    ((s, gm) : _) -> do
      putStrLn ("smallest (program " <> show s <> ", shrunk):")
      TIO.putStr (generatedSource gm)
      printInputs gm
      let ss = summaries gm
      forM_ ss $ \(name, sm) -> do
        putStrLn (T.unpack name <> ":")
        case [x | (n, x) <- ss, n /= name] of
          (other : _) -> mapM_ (TIO.putStrLn . ("  " <>)) (changedOnly gm sm other sm)
          [] -> mapM_ (TIO.putStrLn . ("  " <>)) (renderSummary gm sm)
      when (isJust (optOut o)) (hPutStrLn stderr "note: --out applies to --engine only")
      pure (ExitFailure 1)

tshow :: Show a => a -> Text
tshow = T.pack . show
