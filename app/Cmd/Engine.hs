-- | @stref engine@: the reference engine as an external program speaking
-- stref-engine/1. It reads one request on standard input and writes one
-- answer on standard output. Policies given here override the request's,
-- so @stref engine --policy overflow=wrap@ behaves as a wrap engine.
-- With @--persistent@ it answers request after request, one a line, until
-- the end of its input (conformance/README.md, "Persistent engines").
module Cmd.Engine (Cmd.Engine.command) where

import Cmd.PolicyOptions
import qualified Data.ByteString as BS
import qualified Data.ByteString.Char8 as BSC
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
import System.IO (hFlush, isEOF, stderr, stdin, stdout)

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "engine"
    ( info
        (run <$> switch (long "persistent" <> help "Answer many requests, one JSON request a line on stdin, one answer a line on stdout, until the end of the input (stref conformance --persistent)") <*> policyAssignmentOption)
        (progDesc "Answer one stref-engine/1 request (stdin) with the reference semantics (stdout); with --persistent, one request a line until the end of the input")
    )

run :: Bool -> [(Text, Text)] -> IO ExitCode
run persistent overrides =
  -- the names are checked here so that a typo is a usage error, not an
  -- "unsupported" answer for every case
  case mapM_ (\(k, v) -> setPolicy k v mastertoolXE) overrides of
    Left e -> TIO.hPutStrLn stderr ("stref engine: " <> e) >> pure (ExitFailure 2)
    Right ()
      | persistent -> serve
      | otherwise -> BL.getContents >>= answer
  where
    answer input = case decodeRequest input of
      Left e -> do
        TIO.hPutStrLn stderr ("stref engine: the request is not a valid stref-engine/1 request: " <> T.pack e)
        pure (ExitFailure 2)
      Right rq -> do
        -- one line: the JSON encoding escapes every newline of the source
        BLC.putStrLn (encodeAnswer (referenceEngine overrides rq))
        hFlush stdout
        pure ExitSuccess
    -- a request that is not valid ends the engine (exit 2), as without
    -- --persistent: the runner reports it and starts another
    serve = do
      eof <- isEOF
      if eof
        then pure ExitSuccess
        else do
          line <- BS.hGetLine stdin
          if BSC.all (`elem` (" \t\r" :: String)) line
            then serve
            else answer (BL.fromStrict line) >>= \case
              ExitSuccess -> serve
              failure -> pure failure
