-- | @stref fuzz@: feed mutated programs and random bytes through the whole
-- pipeline and stop at the first internal error (an exception, a hang or
-- runaway allocation), writing a shrunk reproducer. Exit 0 when every input
-- ended properly, 1 when an internal error was found, 2 for a usage error.
module Cmd.Fuzz (command) where

import Control.Exception (IOException, try)
import Control.Monad (filterM, forM, when)
import qualified Data.ByteString as BS
import Data.IORef
import qualified Data.Map.Strict as M
import Data.Maybe (catMaybes)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word64)
import GHC.Clock (getMonotonicTimeNSec)
import Options.Applicative hiding (command)
import qualified Options.Applicative as O
import System.Directory (doesDirectoryExist, doesFileExist, listDirectory)
import System.Exit
import System.FilePath (takeExtension, (</>))
import System.IO (hFlush, hPutStrLn, stderr, stdout)
import Stref.Fuzz
import Stref.Source (decodeSource)

data Options = Options
  { optCount :: Int
  , optSeed :: Maybe Word64
  , optFrom :: Int
  , optSeedDirs :: [FilePath]
  , optOut :: FilePath
  , optTimeout :: Int
  , optProgress :: Int
  }

command :: Mod CommandFields (IO ExitCode)
command =
  O.command "fuzz" $
    info
      (run <$> options)
      (progDesc "Run generated inputs (mutated programs, deep nesting, huge literals, invalid UTF-8, random bytes) through parse, check and run; stop at the first internal error and write a shrunk reproducer. Exit 0 if none, 1 if one was found, 2 for a usage error")

options :: Parser Options
options =
  Options
    <$> option auto (long "count" <> short 'n' <> metavar "N" <> value 1000 <> showDefault <> help "How many inputs to run")
    <*> optional (option auto (long "seed" <> metavar "S" <> help "Campaign seed (default: from the clock; always printed)"))
    <*> option auto (long "from" <> metavar "I" <> value 0 <> showDefault <> help "Index of the first input (to resume or reproduce input I of a seed)")
    <*> many (strOption (long "programs" <> metavar "DIR" <> help "Directory searched for .st seed programs (default: conformance and test/examples)"))
    <*> strOption (long "out" <> metavar "FILE" <> value "fuzz-failure.st" <> showDefault <> help "Where to write the shrunk input of an internal error")
    <*> option auto (long "timeout" <> metavar "SECONDS" <> value 30 <> showDefault <> help "Wall-clock guard per input; exceeding it (and then three times it) counts as a hang")
    <*> option auto (long "progress" <> metavar "N" <> value 10000 <> showDefault <> help "Print progress every N inputs")

run :: Options -> IO ExitCode
run opts
  | optCount opts < 0 || optFrom opts < 0 || optTimeout opts <= 0 || optTimeout opts > 3600 || optProgress opts <= 0 =
      usage "--count and --from take a number >= 0, --timeout 1 to 3600 seconds, --progress a number > 0"
  | otherwise = do
      seed <- maybe ((`mod` 1000000007) <$> getMonotonicTimeNSec) pure (optSeed opts)
      let dirs = if null (optSeedDirs opts) then ["conformance", "test/examples"] else optSeedDirs opts
      files <- concat <$> mapM stFiles dirs
      programs <- catMaybes <$> forM files readProgram
      putStrLn ("stref fuzz: seed " <> show seed <> ", inputs " <> show (optFrom opts) <> ".." <> show (optFrom opts + optCount opts - 1) <> ", " <> show (length programs) <> " seed programs")
      hFlush stdout
      counts <- newIORef (M.empty :: M.Map Text Int)
      let guard = defaultGuard {gTimeMicros = optTimeout opts * 1000000}
          progress i v = do
            modifyIORef' counts (M.insertWith (+) (category v) 1)
            let done = i - optFrom opts + 1
            when (done `mod` optProgress opts == 0) $ do
              cs <- readIORef counts
              putStrLn ("  " <> show done <> " inputs: " <> T.unpack (T.intercalate ", " [k <> " " <> T.pack (show n) | (k, n) <- M.toList cs]))
              hFlush stdout
      report <- fuzzCampaign guard programs seed (optFrom opts) (optCount opts) progress
      case frFailure report of
        Nothing -> do
          putStrLn ("stref fuzz: " <> show (frRun report) <> " inputs, seed " <> show seed <> ": no internal error")
          pure ExitSuccess
        Just (i, why, _, small) -> do
          written <- try (BS.writeFile (optOut opts) small) :: IO (Either IOException ())
          hPutStrLn stderr ("stref fuzz: internal error on input " <> show i <> " of seed " <> show seed <> ": " <> T.unpack why)
          hPutStrLn stderr $ case written of
            Right () -> "  shrunk input (" <> show (BS.length small) <> " bytes) written to " <> optOut opts <> "; reproduce with: stref fuzz --seed " <> show seed <> " --from " <> show i <> " --count 1"
            Left e -> "  could not write " <> optOut opts <> ": " <> show e
          pure (ExitFailure 1)
  where
    usage msg = hPutStrLn stderr ("stref fuzz: " <> msg) >> pure (ExitFailure 2)
    category = \case
      InternalError _ -> "internal-error"
      Fine o -> case o of
        InvalidEncoding -> "invalid-encoding"
        SyntaxErrorKind _ -> "syntax-error"
        RejectedKinds _ -> "rejected"
        Ran codes
          | all (== Nothing) codes -> "ran"
          | otherwise -> "runtime-error"

-- | The .st files under a directory (none if it does not exist).
stFiles :: FilePath -> IO [FilePath]
stFiles dir = do
  isDir <- doesDirectoryExist dir
  if not isDir
    then pure []
    else do
      entries <- either (const []) id <$> (try (listDirectory dir) :: IO (Either IOException [FilePath]))
      let paths = map (dir </>) entries
      subdirs <- filterM doesDirectoryExist paths
      files <- filterM (\p -> (takeExtension p == ".st" &&) <$> doesFileExist p) paths
      (files ++) . concat <$> mapM stFiles subdirs

readProgram :: FilePath -> IO (Maybe Text)
readProgram f = do
  r <- try (BS.readFile f) :: IO (Either IOException BS.ByteString)
  pure $ case r of
    Right bs | Right t <- decodeSource bs -> Just t
    _ -> Nothing
