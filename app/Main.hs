-- | The stref command line. Each command lives in its own module under Cmd/
-- and contributes one optparse-applicative command; exit codes: 0 success,
-- 1 a negative answer (syntax error, rejected program, failed cases),
-- 2 a usage error, 3 an internal error (see 'lastDefence').
module Main (main) where

import Options.Applicative
import System.Environment (getArgs, getProgName)
import Control.Exception (AsyncException (..), SomeException, fromException, try)
import System.Exit
import System.IO (hFlush, hPutStrLn, stderr, stdout)
import System.IO.Error (ioeGetErrorType, ioeGetHandle)
import GHC.IO.Exception (IOErrorType (ResourceVanished))
import qualified Stref
import qualified Cmd.Adapter
import qualified Cmd.Check
import qualified Cmd.Conformance
import qualified Cmd.Coverage
import qualified Cmd.Engine
import qualified Cmd.Eval
import qualified Cmd.Explore
import qualified Cmd.Fuzz
import qualified Cmd.Matrix
import qualified Cmd.Parse
import qualified Cmd.Report
import qualified Cmd.Request
import qualified Cmd.Run

commands :: Mod CommandFields (IO ExitCode)
commands =
  mempty <> Cmd.Parse.command <> Cmd.Check.command <> Cmd.Run.command <> Cmd.Eval.command
    <> Cmd.Conformance.command <> Cmd.Request.command <> Cmd.Engine.command <> Cmd.Coverage.command <> Cmd.Explore.command
    <> Cmd.Fuzz.command <> Cmd.Adapter.command <> Cmd.Matrix.command <> Cmd.Report.command

main :: IO ()
main = do
  args <- getArgs
  prog <- getProgName
  let opts =
        info
          (helper <*> versionOption <*> hsubparser commands)
          (fullDesc <> progDesc "Executable reference semantics of IEC 61131-3 Structured Text" <> header "stref - ST reference interpreter and conformance runner")
      versionOption = infoOption ("stref " ++ Stref.version) (long "version" <> help "Print the version")
  case execParserPure (prefs (showHelpOnEmpty <> showHelpOnError)) opts args of
    Success act -> try (act <* hFlush stdout) >>= either lastDefence exitWith
    Failure f -> do
      let (msg, code) = renderFailure f prog
      case code of
        ExitSuccess -> putStrLn msg >> exitSuccess
        _ -> hPutStrLn stderr msg >> exitWith (ExitFailure 2)
    CompletionInvoked c -> do
      msg <- execCompletion c prog
      putStr msg >> exitSuccess

-- | The library never throws on any input; this is the last line of defence
-- should it ever happen (or should the machine run out of stack or memory):
-- a clear message and exit code 3 instead of a bare Haskell exception.
lastDefence :: SomeException -> IO ()
lastDefence e
  | Just (code :: ExitCode) <- fromException e = exitWith code
  | Just StackOverflow <- fromException e =
      failWith "the input is too large or too deeply nested for the stack; raise the limit with +RTS -K<size> -RTS (e.g. -K2g)"
  | Just HeapOverflow <- fromException e = failWith "out of memory"
  | Just UserInterrupt <- fromException e = exitWith (ExitFailure 130)
  -- the reader of the output went away (@stref run ... | head@): stop
  -- quietly, with the status of a process ended by SIGPIPE
  | Just ioe <- fromException e
  , ioeGetErrorType ioe == ResourceVanished
  , ioeGetHandle ioe == Just stdout =
      exitWith (ExitFailure 141)
  | otherwise = failWith ("internal error: " <> show e <> "; please report it with the input that caused it")
  where
    failWith msg = hPutStrLn stderr ("stref: " <> msg) >> exitWith (ExitFailure 3)
