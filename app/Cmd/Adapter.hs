-- | @stref adapter ENGINE@: a real engine installed by the user, as an
-- external program speaking stref-engine/1 (docs/engines.md). It reads one
-- request on standard input and writes the engine's answer on standard
-- output; @stref conformance --engine matiec@ runs it once per case.
-- Exit 2 when the engine is not installed or the request is malformed, 1
-- when the adapter failed on this case (the runner's @engine-error@).
module Cmd.Adapter (Cmd.Adapter.command) where

import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Protocol (decodeRequest, encodeAnswer)
import Stref.Engines.Run
import System.Exit
import System.IO (stderr)

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "adapter"
    ( info
        (run <$> strArgument (metavar "ENGINE" <> help ("One of: " <> unwords [T.unpack (engName e) | e <- engines])) <*> switch (long "check" <> help "Only say whether the engine is installed (exit 0) or not (exit 2)"))
        (progDesc "Answer one stref-engine/1 request (stdin) with a real engine the user installed (docs/engines.md)")
    )

run :: String -> Bool -> IO ExitCode
run name checkOnly = case engineByName (T.pack name) of
  Nothing -> do
    TIO.hPutStrLn stderr ("stref adapter: no adapter for '" <> T.pack name <> "'; there are: " <> T.intercalate ", " (map engName engines))
    pure (ExitFailure 2)
  Just e -> do
    found <- findTools e
    case found of
      Left why -> TIO.hPutStrLn stderr ("stref adapter: " <> why) >> pure (ExitFailure 2)
      Right tools
        | checkOnly -> TIO.putStrLn (engTitle e <> ": " <> toolsText tools) >> pure ExitSuccess
        | otherwise -> do
            input <- BL.getContents
            case decodeRequest input of
              Left err -> do
                TIO.hPutStrLn stderr ("stref adapter: the request is not a valid stref-engine/1 request: " <> T.pack err)
                pure (ExitFailure 2)
              Right rq -> do
                answer <- answerWith tools rq
                case answer of
                  Left why -> TIO.hPutStrLn stderr ("stref adapter: " <> why) >> pure (ExitFailure 1)
                  Right a -> BLC.putStrLn (encodeAnswer a) >> pure ExitSuccess
