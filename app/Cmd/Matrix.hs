-- | @stref matrix@: every IEC dialect's corpus against every engine the user
-- installed (docs/engines.md), written as data and as one static page.
-- @--from-data@ only draws the page again from the data, without engines.
module Cmd.Matrix (Cmd.Matrix.command) where

import Control.Exception (SomeException, try)
import Control.Monad (forM, when)
import qualified Data.Aeson as A
import qualified Data.ByteString.Lazy as BL
import qualified Data.Map.Strict as M
import Data.Maybe (catMaybes)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Data.Time (getCurrentTime, utctDay)
import GHC.Conc (getNumProcessors, setNumCapabilities)
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Corpus
import Stref.Conformance.Matrix
import Stref.Conformance.Report (summaryLine, totals)
import Stref.Conformance.Rules (Rule (..))
import Stref.Conformance.Runner
import Stref.Engines.Run
import Cmd.Common (adapterCommand)
import System.Directory (createDirectoryIfMissing, doesDirectoryExist)
import System.Exit
import System.FilePath ((</>))
import System.IO (stderr)
import System.Process (readProcessWithExitCode)

data Opts = Opts
  { oCorpus :: FilePath
  , oOut :: FilePath
  , oEngines :: [String]
  , oDialects :: [String]
  , oLabels :: [String]
  , oJobs :: Int
  , oFromData :: Bool
  }

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "matrix"
    ( info
        (run <$> opts)
        (progDesc "Run every IEC dialect's corpus against every installed engine; write the matrix as data (matrix.json) and as a page (index.html)")
    )
  where
    opts =
      Opts
        <$> strOption (long "corpus" <> metavar "DIR" <> value "conformance" <> showDefault <> help "The corpus: one directory per dialect")
        <*> strOption (long "out" <> metavar "DIR" <> value ("docs" </> "matrix") <> showDefault <> help "Where matrix.json and index.html go")
        <*> many (strOption (long "engine" <> metavar "NAME" <> help "Only this engine (repeatable; default: every engine stref has an adapter for)"))
        <*> many (strOption (long "dialect" <> metavar "NAME" <> help "Only this dialect (repeatable; default: tecomat and nexto)"))
        <*> many (strOption (long "label" <> metavar "ENGINE=TEXT" <> help "What to record of an engine's version beside what it says itself, e.g. matiec=6bb2c33"))
        <*> option auto (short 'j' <> long "jobs" <> metavar "N" <> value 2 <> showDefault <> help "Cases run in parallel")
        <*> switch (long "from-data" <> help "Only draw index.html again from the matrix.json in --out")

run :: Opts -> IO ExitCode
run o
  | oFromData o = do
      raw <- BL.readFile (oOut o </> "matrix.json")
      case A.eitherDecode raw of
        Left e -> TIO.hPutStrLn stderr ("stref matrix: " <> T.pack (oOut o </> "matrix.json") <> " is not matrix data: " <> T.pack e) >> pure (ExitFailure 2)
        Right v -> writePage v >> pure ExitSuccess
  | otherwise = do
      let wanted = if null (oEngines o) then engines else [e | e <- engines, T.unpack (engName e) `elem` oEngines o]
          dialects = if null (oDialects o) then ["tecomat", "nexto"] else oDialects o
      cores <- getNumProcessors
      setNumCapabilities (max 1 (min (oJobs o) cores))
      found <- forM wanted $ \e -> do
        tools <- findTools e
        case tools of
          Left why -> TIO.hPutStrLn stderr ("stref matrix: skipped " <> engName e <> ": " <> why) >> pure Nothing
          Right t -> pure (Just (e, t))
      let installed = catMaybes found
      when (null installed) $ TIO.hPutStrLn stderr "stref matrix: no engine is installed (docs/engines.md says how to point stref at one)"
      corpora <- forM dialects $ \d -> do
        let path = oCorpus o </> d
        exists <- doesDirectoryExist path
        if exists then Just . (d,) <$> loadCorpusWith (oJobs o) [path] else pure Nothing
      let loaded = catMaybes corpora
          titles = M.fromList [(ruleId r, ruleTitle r) | (_, c) <- loaded, rs <- M.elems (corpusRules c), r <- rs]
      runs <- fmap concat . forM installed $ \(e, t) -> do
        version <- engineVersion t
        adapter <- adapterCommand e
        let label = [T.drop 1 rest | l <- oLabels o, let (n, rest) = T.breakOn "=" (T.pack l), n == engName e]
        forM loaded $ \(d, corpus) -> do
          let options =
                defaultRunOptions
                  { roEngine = External adapter
                  , roJobs = oJobs o
                  , roTimeout = 60
                  }
          results <- runCorpus options corpus
          TIO.hPutStrLn stderr (engName e <> " / " <> T.pack d <> ": " <> summaryLine (totals results))
          pure (MatrixRun (engName e) (engTitle e) (T.intercalate ", " (version : label)) (T.pack d) results)
      day <- T.pack . show . utctDay <$> getCurrentTime
      commit <- gitCommit
      let v = matrixData day commit titles runs
      createDirectoryIfMissing True (oOut o)
      BL.writeFile (oOut o </> "matrix.json") (A.encode v <> "\n")
      writePage v
      pure ExitSuccess
  where
    writePage v = do
      createDirectoryIfMissing True (oOut o)
      TIO.writeFile (oOut o </> "index.html") (matrixPage v)
      TIO.hPutStrLn stderr ("stref matrix: wrote " <> T.pack (oOut o </> "index.html"))

gitCommit :: IO Text
gitCommit = do
  r <- try (readProcessWithExitCode "git" ["rev-parse", "--short", "HEAD"] "")
  pure $ case r of
    Right (ExitSuccess, out, _) -> T.strip (T.pack out)
    Right _ -> "unknown"
    Left (_ :: SomeException) -> "unknown"
