-- | @stref parse FILE [--ast] [--policy K=V]...@: read an ST module, print it
-- normalised (or its syntax tree), or print the syntax error.
module Cmd.Parse (command) where

import Control.Exception (IOException, try)
import Control.Monad (foldM)
import qualified Data.Text as T
import qualified Data.ByteString as BS
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative as O
import System.Exit
import System.IO (hPutStrLn, stderr)
import System.IO.Error (ioeGetErrorString, isDoesNotExistError)
import Cmd.Common (readSource)
import Cmd.Iec (dialectPolicies, isIecDialect, parseIec)
import Stref.Source (decodeSource, renderEncodingError)
import Stref.Policy (mastertoolXE, setPolicy)
import Stref.Syntax (Module, Pos)
import Stref.Syntax.Parser (parseModule)
import Stref.Syntax.Pretty (prettyModule)
import Stref.Verification (renderError)

data Options = Options
  { _optFile :: FilePath
  , _optAst :: Bool
  , _optPolicies :: [String]
  , _optDialect :: String
  }

command :: Mod CommandFields (IO ExitCode)
command =
  O.command "parse" $
    info
      (run <$> options)
      (progDesc "Parse an ST module; print it normalised, or its syntax tree with --ast (exit 0), or the syntax error (exit 1)")

options :: Parser Options
options =
  Options
    <$> strArgument (metavar "FILE" <> help "The ST source file")
    <*> switch (long "ast" <> help "Print the syntax tree instead of the normalised program")
    <*> many (strOption (long "policy" <> metavar "K=V" <> help "Set a policy, e.g. nested-comments=yes or elsif-keyword=ELSIF"))
    <*> strOption (long "dialect" <> metavar "NAME" <> value "mastertool-xe" <> showDefault <> help "The dialect: mastertool-xe, tecomat or nexto (an IEC dialect prints the declarations of the unit, or its syntax tree with --ast)")

run :: Options -> IO ExitCode
run (Options file ast policyArgs dialect) = case dialectPolicies dialect policyArgs of
  Left msg -> usage msg
  Right pol | isIecDialect pol -> do
    src <- readSource file
    either usage (\s -> parseIec pol file s ast) src
  Right _ -> runMasterTool file ast policyArgs
  where
    usage msg = do
      hPutStrLn stderr ("stref parse: " <> T.unpack msg)
      pure (ExitFailure 2)

runMasterTool :: FilePath -> Bool -> [String] -> IO ExitCode
runMasterTool file ast policyArgs =
  case foldM applyPolicy mastertoolXE policyArgs of
    Left msg -> usage msg
    Right policies -> do
      contents <- try (BS.readFile file) :: IO (Either IOException BS.ByteString)
      case contents of
        Left e
          | isDoesNotExistError e -> usage ("cannot read " <> T.pack file <> ": there is no such file")
          | otherwise -> usage ("cannot read " <> T.pack file <> ": " <> T.pack (ioeGetErrorString e))
        Right bytes -> do
          case decodeSource bytes of
           Left bad -> do
            TIO.hPutStr stderr (renderEncodingError file bad)
            pure (ExitFailure 1)
           Right source -> case parseModule policies file source of
            Left err -> do
              TIO.hPutStr stderr (renderError file source err)
              pure (ExitFailure 1)
            Right m -> do
              if ast
                then putStrLn (layoutShow (show (m :: ModulePos)))
                else TIO.putStr (prettyModule m)
              pure ExitSuccess
  where
    applyPolicy p kv = case T.breakOn "=" (T.pack kv) of
      (k, v) | not (T.null v) -> setPolicy k (T.drop 1 v) p
      _ -> Left ("--policy takes K=V, not '" <> T.pack kv <> "'")
    usage msg = do
      hPutStrLn stderr ("stref parse: " <> T.unpack msg)
      pure (ExitFailure 2)

type ModulePos = Module Pos

-- | The derived 'Show' text of the tree laid out one field or element per
-- line, indented by nesting; positions stay on one line.
layoutShow :: String -> String
layoutShow = go []
  where
    go :: String -> String -> String
    go stack = \case
      [] -> []
      '"' : rest -> let (lit, rest') = stringLiteral rest in '"' : lit ++ go stack rest'
      'P' : 'o' : 's' : ' ' : '{' : rest -> oneLine "Pos {" rest
      'I' : 'd' : 'e' : 'n' : 't' : ' ' : '{' : rest -> oneLine "Ident {" rest
      '[' : ']' : rest -> "[]" ++ go stack rest
      c : rest
        | c == '{' || c == '[' -> c : newline (depth stack + 1) ++ go (c : stack) (dropWhile (== ' ') rest)
        | c == '(' -> c : go (c : stack) rest
        | c == '}' || c == ']' -> newline (depth stack - 1) ++ c : go (drop 1 stack) rest
        | c == ')' -> c : go (drop 1 stack) rest
        | c == ',', (top : _) <- stack, top /= '(' -> ',' : newline (depth stack) ++ go stack (dropWhile (== ' ') rest)
        | otherwise -> c : go stack rest
      where
        -- a small record (a position, a name) stays on its line
        oneLine open rest =
          let (inside, rest') = break (== '}') rest
           in open ++ inside ++ "}" ++ go stack (drop 1 rest')
    depth = length . filter (/= '(')
    newline n = '\n' : replicate (2 * max 0 n) ' '
    -- the rest of a string literal, escapes included, and what follows it
    stringLiteral = \case
      [] -> ([], [])
      '\\' : x : rest -> let (l, r) = stringLiteral rest in ('\\' : x : l, r)
      '"' : rest -> ("\"", rest)
      x : rest -> let (l, r) = stringLiteral rest in (x : l, r)
