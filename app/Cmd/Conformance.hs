-- | @stref conformance [PATH...]@: run the conformance corpus against the
-- reference interpreter or an external engine (conformance/README.md).
-- Exit 1 when a case failed, a case file is malformed or an engine
-- misbehaved (known failures excepted); 2 on a usage error, a selection
-- that matches no case, or an engine that cannot be started.
module Cmd.Conformance (Cmd.Conformance.command) where

import Cmd.PolicyOptions
import Control.Monad (when)
import Data.Maybe (fromMaybe, isJust)
import GHC.Conc (getNumProcessors, setNumCapabilities)
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Case (Case (..), effectiveExpect)
import Stref.Conformance.Corpus
import Stref.Conformance.Report
import Stref.Conformance.Runner
import Cmd.Common (engineCommand, sourceLine)
import Stref.Engines.Run (engineByName)
import Stref.Engine (referenceTrace)
import Stref.Policy (policyAssignments)
import Stref.Trace (items, renderText)
import System.Exit
import System.IO (stderr)
import Text.Read (readMaybe)

data Format = FormatText | FormatJson | FormatJunit

data Opts = Opts
  { oPaths :: [FilePath]
  , oEngine :: Maybe String
  , oPreset :: Maybe Text
  , oPolicies :: [(Text, Text)]
  , oJobs :: Int
  , oShard :: Maybe (Int, Int)
  , oFilters :: [Text]
  , oFeatures :: [Text]
  , oExcluded :: [Text]
  , oFeaturesFile :: Maybe FilePath
  , oRules :: [Text]
  , oTimeout :: Maybe Double
  , oFormat :: Format
  , oOutput :: Maybe FilePath
  , oKnown :: Maybe FilePath
  , oMaxAnswer :: Int
  , oVerbose :: Bool
  , oOnlyFailures :: Bool
  , oExplain :: Bool
  , oPersistent :: Bool
  }

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "conformance"
    ( info
        (run <$> opts)
        (progDesc "Run the conformance corpus against the reference interpreter or an external engine")
    )

opts :: Parser Opts
opts =
  Opts
    <$> many (strArgument (metavar "PATH..." <> help "Corpus directories or case files (default: conformance)"))
    <*> optional (strOption (long "engine" <> metavar "'CMD ARGS'" <> help "External engine: a shell command started once per case (request on stdin, answer on stdout)"))
    <*> optional presetChoice
    <*> policyAssignmentOption
    <*> option positive (short 'j' <> long "jobs" <> metavar "N" <> value 1 <> showDefault <> help "Cases run in parallel")
    <*> optional (option shard (long "shard" <> metavar "I/N" <> help "Run only part I of N (1-based) of the cases, in id order"))
    <*> many (strOption (long "filter" <> metavar "GLOB" <> help "Run only cases whose id matches (* any text, ? one character; repeatable)"))
    <*> many (strOption (long "feature" <> metavar "F" <> help "Run only cases tagged with this feature (repeatable)"))
    <*> many (strOption (long "exclude-feature" <> metavar "F" <> help "A feature the engine lacks: its cases are unsupported, the engine is not asked (repeatable)"))
    <*> optional (strOption (long "features-file" <> metavar "FILE" <> help "The features the engine lacks, one a line (# comments), as --exclude-feature; names no case has are ignored"))
    <*> many (strOption (long "rule" <> metavar "ID" <> help "Run only cases citing this rule (repeatable)"))
    <*> optional (option seconds (long "timeout" <> metavar "SECONDS" <> help "Time limit per case (default: 10 for an external engine; 300 for the reference, whose runs the step budget already bounds)"))
    <*> option format (long "format" <> metavar "text|json|junit" <> value FormatText <> help "Report format (default text)")
    <*> optional (strOption (long "output" <> metavar "FILE" <> help "Write the report to FILE and the text summary to stdout"))
    <*> optional (strOption (long "known-failures" <> metavar "FILE" <> help "Case ids (one a line) whose failure is expected: reported as skipped"))
    <*> option positive (long "max-answer-bytes" <> metavar "N" <> value (16 * 1024 * 1024) <> showDefault <> help "Largest answer accepted from an external engine")
    <*> switch (long "verbose" <> short 'v' <> help "List every case, also passed and filtered-out ones, and for a case an external engine failed the request and its answer")
    <*> switch (long "only-failures" <> help "In the text report, list only the cases that fail the run (fail, engine-error, invalid); the totals are unchanged")
    <*> switch (long "explain" <> help "For one case: print the reference's trace of it (every statement, value and deciding rule, docs/trace.md) before the report, which shows the differences of the engine's answer")
    <*> switch (long "persistent" <> help "The --engine answers many requests in one process: one JSON request a line on its stdin, one answer a line on its stdout (e.g. 'stref engine --persistent'); restarted after a crash, a hang or a bad answer")
  where
    positive = eitherReader $ \s -> case readMaybe s of
      Just n | n >= 1 -> Right n
      _ -> Left ("expected a positive number, not '" <> s <> "'")
    seconds = eitherReader $ \s -> case readMaybe s :: Maybe Double of
      Just x | x > 0 -> Right x
      _ -> case readMaybe s :: Maybe Int of
        Just n | n > 0 -> Right (fromIntegral n)
        _ -> Left ("expected a positive number of seconds, not '" <> s <> "'")
    shard = eitherReader $ \s -> case break (== '/') s of
      (a, '/' : b) | Just i <- readMaybe a, Just n <- readMaybe b, n >= 1, i >= 1, i <= n -> Right (i, n)
      _ -> Left ("expected I/N with 1 <= I <= N, e.g. 2/4, not '" <> s <> "'")
    format = eitherReader $ \case
      "text" -> Right FormatText
      "json" -> Right FormatJson
      "junit" -> Right FormatJunit
      s -> Left ("expected text, json or junit, not '" <> s <> "'")

usage :: Text -> IO ExitCode
usage msg = TIO.hPutStrLn stderr ("stref conformance: " <> msg) >> pure (ExitFailure 2)

-- | @--explain@: the reference's trace of the one case selected.
explain :: RunOptions -> Corpus -> IO ()
explain options corpus = case [c | Loaded c <- corpusEntries corpus, selected c] of
  [c] -> case casePolicies options c of
    Left e -> usage e >>= exitWith
    Right pol -> case referenceTrace [] (buildRequest pol c (effectiveExpect pol c)) of
      Left e -> usage e >>= exitWith
      Right (ran, _, events) -> do
        TIO.putStrLn ("the reference's trace of " <> caseId c <> " (" <> T.pack (caseFile c) <> "):")
        mapM_ TIO.putStrLn (renderText ran (sourceLine (caseSource c)) (items events))
        TIO.putStrLn ""
  cs -> usage ("--explain explains one case; " <> T.pack (show (length cs)) <> " are selected (give one case file, or --filter ID)") >>= exitWith
  where
    selected c = null (roFilters options) || any (`globMatch` caseId c) (roFilters options)

run :: Opts -> IO ExitCode
run o = case resolvePolicies (maybe "mastertool-xe" id (oPreset o)) (oPolicies o) of
  Left e -> usage e
  Right policies -> do
    known <- maybe (pure (Right S.empty)) readKnownFailures (oKnown o)
    case known of
      Left e -> usage e
      Right knownSet -> do
        declared <- maybe (pure (Right [])) (readListFile "features") (oFeaturesFile o)
        lackingFile <- either (\e -> usage e >>= exitWith) pure declared
        let paths = if null (oPaths o) then ["conformance"] else oPaths o
        -- the cases are parsed, and the reference engine computes, in this
        -- process: use the cores
        cores <- getNumProcessors
        when (oJobs o > 1) (setNumCapabilities (max 1 (min (oJobs o) cores)))
        -- a named engine is its adapter, run as this program
        adapter <- maybe (pure (Right Nothing)) (fmap (fmap Just) . engineCommand) (oEngine o)
        either (\why -> usage why >>= exitWith) (const (pure ())) adapter
        let isAdapter = isJust (oEngine o >>= engineByName . T.pack)
        when (oPersistent o && (null (oEngine o) || isAdapter)) $
          usage "--persistent is for an --engine command that answers one request a line (the reference and the adapters of real engines run without it)" >>= exitWith
        corpus <- loadCorpusWith (oJobs o) paths
        mapM_ (TIO.hPutStrLn stderr) (corpusErrors corpus)
        if null (corpusEntries corpus)
          then usage ("no case files (*.st) under " <> T.intercalate ", " (map T.pack paths))
          else do
            let options =
                  defaultRunOptions
                    { roEngine = maybe (Reference []) External (either (const Nothing) id adapter)
                    , roPolicies = policies
                    -- without --preset, every case runs under its own dialect's preset
                    , roOverrides = maybe (Just (oPolicies o)) (const Nothing) (oPreset o)
                    , roJobs = oJobs o
                    , roShard = oShard o
                    , roFilters = oFilters o
                    , roFeatures = oFeatures o
                    , roLacking = oExcluded o ++ lackingFile
                    , roExcludeGiven = oExcluded o
                    , roRules = oRules o
                    , roTimeout = fromMaybe (maybe 300 (const (if isAdapter then 60 else 10)) (oEngine o)) (oTimeout o)
                    , roKnownFailures = knownSet
                    , roMaxAnswerBytes = oMaxAnswer o
                    , roPersistent = oPersistent o
                    }
            case unmatchedSelections options corpus of
              [] -> pure ()
              nothing -> mapM_ usage nothing >> exitWith (ExitFailure 2)
            when (oExplain o) $ explain options corpus
            results <- runCorpusUnlessEngineMissing options corpus >>= \case
              Right rs -> pure rs
              Left why -> usage (why <> "; check the command given to --engine: " <> maybe "" T.pack (oEngine o)) >>= exitWith
            let ids = S.fromList (map resId results)
                staleKnown = [k | k <- S.toList knownSet, k `S.notMember` ids]
                nowPassing = [resId r | r <- results, resKnownFailure r, Pass <- [resOutcome r]]
                engineName = maybe "reference" T.pack (oEngine o)
                text = textReport TextOptions {toVerbose = oVerbose o, toOnlyFailures = oOnlyFailures o, toRuleTitles = ruleTitles corpus} results
                report = case oFormat o of
                  FormatText -> BL.fromStrict (TE.encodeUtf8 text)
                  FormatJson -> jsonReport engineName (policyAssignments policies) results <> "\n"
                  FormatJunit -> junitReport (ruleTitles corpus) results
            mapM_ (\k -> TIO.hPutStrLn stderr ("note: known failure " <> k <> " is not among the cases run")) (if null (oFilters o) && null (oFeatures o) && null (oRules o) && oShard o == Nothing then staleKnown else [])
            mapM_ (\k -> TIO.hPutStrLn stderr ("note: known failure " <> k <> " passes now; remove it from the list")) nowPassing
            case oOutput o of
              Just file -> BL.writeFile file report >> TIO.putStr text
              Nothing -> BLC.putStr report
            pure (if any failing results || not (null (corpusErrors corpus)) then ExitFailure 1 else ExitSuccess)
