-- | @stref engine@: the reference engine as an external program speaking
-- stref-engine/1. It reads one request on standard input and writes one
-- answer on standard output. Policies given here override the request's,
-- so @stref engine --policy overflow=wrap@ behaves as a wrap engine.
module Cmd.Engine (Cmd.Engine.command) where

import Cmd.PolicyOptions
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Protocol (decodeRequest, encodeAnswer)
import Stref.Engine (referenceEngine)
import Stref.Policy (mastertoolXE, setPolicy)
import System.Exit
import System.IO (stderr)

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "engine"
    ( info
        (run <$> policyAssignmentOption)
        (progDesc "Answer one stref-engine/1 request (stdin) with the reference semantics (stdout)")
    )

run :: [(Text, Text)] -> IO ExitCode
run overrides =
  -- the names are checked here so that a typo is a usage error, not an
  -- "unsupported" answer for every case
  case mapM_ (\(k, v) -> setPolicy k v mastertoolXE) overrides of
    Left e -> TIO.hPutStrLn stderr ("stref engine: " <> e) >> pure (ExitFailure 2)
    Right () -> do
      input <- BL.getContents
      case decodeRequest input of
        Left e -> do
          TIO.hPutStrLn stderr ("stref engine: the request is not a valid stref-engine/1 request: " <> T.pack e)
          pure (ExitFailure 2)
        Right rq -> do
          BLC.putStrLn (encodeAnswer (referenceEngine overrides rq))
          pure ExitSuccess
