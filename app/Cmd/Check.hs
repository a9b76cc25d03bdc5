-- | @stref check FILE [--format text|json|gcc] [--module P|F] [--policy K=V]...@:
-- verify an ST module (catalogue §10). Exit 0 when it is valid, 1 when it is
-- rejected (syntax or verification errors), 2 on a usage error.
module Cmd.Check (command) where

import Control.Exception (IOException, try)
import Control.Monad (foldM, when)
import Data.Aeson ((.=))
import qualified Data.Aeson as A
import qualified Data.ByteString as BS
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative as O
import Cmd.Common (notAFile, portabilitySummary, readSource)
import Cmd.Iec (checkIec, dialectPolicies, isIecDialect)
import Stref.Source (decodeSource, renderEncodingError)
import Stref.Check (checkModule)
import Stref.Checked (ModuleKind (..))
import Stref.Policy (mastertoolXE, setPolicy)
import Stref.Portability (moduleWarnings, renderWarning, warningJson)
import Stref.Syntax (Pos (..))
import Stref.Syntax.Parser (parseModule)
import Stref.Verification
import System.Exit
import System.IO (hPutStrLn, stderr)

data Format = FormatText | FormatJson | FormatGcc

data Options = Options
  { optFile :: FilePath
  , optFormat :: Format
  , optKind :: ModuleKind
  , optPolicies :: [String]
  , optDialect :: String
  , optPortability :: Bool
  }

command :: Mod CommandFields (IO ExitCode)
command =
  O.command "check" $
    info
      (run <$> options)
      (progDesc "Verify an ST module (static semantics): exit 0 if valid, 1 with its errors if rejected")

options :: Parser Options
options =
  Options
    <$> strArgument (metavar "FILE" <> help "The ST source file")
    <*> option (eitherReader readFormat) (long "format" <> metavar "text|json|gcc" <> value FormatText <> help "How to print the errors (default text)")
    <*> option (eitherReader readKind) (long "module" <> metavar "P|F" <> value ProcedureModule <> help "Procedure (P, default) or function (F) module")
    <*> many (strOption (long "policy" <> metavar "K=V" <> help "Set a policy, e.g. name-resolution=local-wins"))
    <*> strOption (long "dialect" <> metavar "NAME" <> value "mastertool-xe" <> showDefault <> help "The dialect: mastertool-xe, tecomat or nexto")
    <*> switch (long "portability" <> help "Also list the constructs whose meaning depends on a policy (warnings; the exit status stays 0 for a valid program)")
  where
    readFormat = \case
      "text" -> Right FormatText
      "json" -> Right FormatJson
      "gcc" -> Right FormatGcc
      s -> Left ("unknown format '" <> s <> "' (text, json or gcc)")
    readKind s = case map toUpperAscii s of
      "P" -> Right ProcedureModule
      "F" -> Right FunctionModule
      _ -> Left ("unknown module kind '" <> s <> "' (P or F)")
    toUpperAscii c = if c >= 'a' && c <= 'z' then toEnum (fromEnum c - 32) else c

run :: Options -> IO ExitCode
run opts = case dialectPolicies (optDialect opts) (optPolicies opts) of
  Right pol | isIecDialect pol -> do
    src <- readSource (optFile opts)
    either (\msg -> hPutStrLn stderr ("stref check: " <> T.unpack msg) >> pure (ExitFailure 2)) (\s -> checkIec pol (optFile opts) s (optPortability opts) (isJson (optFormat opts))) src
  Left msg -> hPutStrLn stderr ("stref check: " <> T.unpack msg) >> pure (ExitFailure 2)
  _ -> runMasterTool opts

isJson :: Format -> Bool
isJson = \case
  FormatJson -> True
  _ -> False

runMasterTool :: Options -> IO ExitCode
runMasterTool opts =
  case foldM applyPolicy mastertoolXE (optPolicies opts) of
    Left msg -> usage msg
    Right policies -> notAFile file >>= maybe (checkFile policies) usage
  where
    checkFile policies = do
      contents <- try (BS.readFile file) :: IO (Either IOException BS.ByteString)
      case contents of
        Left e -> usage ("cannot read " <> T.pack file <> ": " <> T.pack (show e))
        Right bytes -> case decodeSource bytes of
         Left bad -> do
          TIO.hPutStr stderr (renderEncodingError file bad)
          pure (ExitFailure 1)
         Right source -> do
          let outcome = case parseModule policies file source of
                Left err -> Left [err]
                Right m -> m <$ checkModule policies (optKind opts) m
          case outcome of
            Right m -> do
              let warnings = if optPortability opts then moduleWarnings m else []
              case optFormat opts of
                FormatJson -> BL.putStrLn (A.encode (A.object (["file" .= file, "valid" .= True, "errors" .= ([] :: [A.Value])] ++ ["warnings" .= map (warningJson policies) warnings | optPortability opts])))
                _ -> do
                  putStrLn (file <> ": valid " <> kindText <> " module")
                  mapM_ (TIO.putStrLn . renderWarning policies file) warnings
                  when (optPortability opts) $ putStrLn (portabilitySummary (length warnings))
              pure ExitSuccess
            Left errs -> do
              case optFormat opts of
                FormatText -> TIO.hPutStr stderr (renderErrors file source errs)
                FormatGcc -> mapM_ (TIO.hPutStrLn stderr . gccLine) errs
                FormatJson -> BL.putStrLn (A.encode (A.object ["file" .= file, "valid" .= False, "errors" .= map jsonError errs]))
              pure (ExitFailure 1)
    file = optFile opts
    kindText = case optKind opts of
      ProcedureModule -> "P"
      FunctionModule -> "F"
    applyPolicy p kv = case T.breakOn "=" (T.pack kv) of
      (k, v) | not (T.null v) -> setPolicy k (T.drop 1 v) p
      _ -> Left ("--policy takes K=V, not '" <> T.pack kv <> "'")
    usage msg = do
      hPutStrLn stderr ("stref check: " <> T.unpack msg)
      pure (ExitFailure 2)
    gccLine :: VerificationError -> Text
    gccLine (VerificationError kind (Pos l c) msg) =
      T.pack file <> ":" <> T.pack (show l) <> ":" <> T.pack (show c) <> ": error: " <> msg <> " [" <> kind <> "]"
    jsonError (VerificationError kind (Pos l c) msg) =
      A.object ["kind" .= kind, "line" .= l, "column" .= c, "message" .= msg]
