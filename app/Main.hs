-- | The stref command line. Each command lives in its own module under Cmd/
-- and contributes one optparse-applicative command; exit codes: 0 success,
-- 1 a negative answer (syntax error, rejected program, failed cases),
-- 2 a usage error.
module Main (main) where

import Options.Applicative
import System.Environment (getArgs, getProgName)
import System.Exit
import System.IO (hPutStrLn, stderr)
import qualified Stref
import qualified Cmd.Check
import qualified Cmd.Conformance
import qualified Cmd.Coverage
import qualified Cmd.Engine
import qualified Cmd.Eval
import qualified Cmd.Parse
import qualified Cmd.Run

commands :: Mod CommandFields (IO ExitCode)
commands =
  mempty <> Cmd.Parse.command <> Cmd.Check.command <> Cmd.Run.command <> Cmd.Eval.command
    <> Cmd.Conformance.command <> Cmd.Engine.command <> Cmd.Coverage.command

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
    Success act -> act >>= exitWith
    Failure f -> do
      let (msg, code) = renderFailure f prog
      case code of
        ExitSuccess -> putStrLn msg >> exitSuccess
        _ -> hPutStrLn stderr msg >> exitWith (ExitFailure 2)
    CompletionInvoked c -> do
      msg <- execCompletion c prog
      putStr msg >> exitSuccess
