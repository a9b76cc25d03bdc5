{-# LANGUAGE MultiWayIf #-}

-- | Helpers shared by the run and eval commands: policies from K=V, reading
-- sources, rendering values and errors.
module Cmd.Common
  ( applyPolicies
  , readSource
  , usageError
  , parseSetting
  , parseSetArg
  , parseBool
  , describeError
  , cellText
  , valueJson
  , engineCommand
  , adapterCommand
  , rejectionJson
  , notAFile
  , TraceFlags (..)
  , traceFlags
  , traceRequest
  , watchTable
  , inSnippet
  , sourceLine
  , portabilitySummary
  , Comparison (..)
  , printComparison
  ) where

import Control.Exception (IOException, try)
import Control.Monad (foldM)
import Control.Monad (forM_)
import qualified Data.Aeson as A
import Data.Aeson ((.=))
import qualified Data.Aeson.Key as K
import qualified Data.ByteString.Lazy.Char8 as BL
import qualified Data.Text.IO as TIO
import qualified Data.ByteString as BS
import Data.Char (isDigit, toUpper)
import Data.Scientific (fromFloatDigits)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import Numeric (readHex)
import Options.Applicative (Parser, help, long, many, metavar, strOption, switch)
import System.Directory (doesDirectoryExist, doesFileExist)
import System.Exit
import System.IO (hPutStrLn, stderr)
import Stref.Engines.Run (Engine, engName, engineByName, findTools)
import System.Environment (getExecutablePath)
import Stref.Source (decodeSource, renderEncodingError)
import Stref.Diagnostics
import Stref.Syntax (Pos (..))
import Stref.Verification (VerificationError (..))
import Stref.Operands
import Stref.Policy
import Stref.Run (Setting (..), observeOperand)
import Stref.Values
import Text.Read (readMaybe)

-- | Apply @--policy K=V@ options to the MasterTool XE preset.
applyPolicies :: [String] -> Either Text Policies
applyPolicies = foldM apply mastertoolXE
  where
    apply p kv = case T.breakOn "=" (T.pack kv) of
      (k, v) | not (T.null v) -> setPolicy k (T.drop 1 v) p
      _ -> Left ("--policy takes K=V, not '" <> T.pack kv <> "'")

readSource :: FilePath -> IO (Either Text Text)
readSource file = do
  missing <- notAFile file
  case missing of
    Just why -> pure (Left why)
    Nothing -> do
      contents <- try (BS.readFile file) :: IO (Either IOException BS.ByteString)
      pure $ case contents of
        Left e -> Left ("cannot read " <> T.pack file <> ": " <> T.pack (show e))
        Right bytes -> either (Left . T.stripEnd . renderEncodingError file) Right (decodeSource bytes)

-- | Why a path given as a source file is none: it does not exist, or it is a
-- directory (in words, not as the exception's text).
notAFile :: FilePath -> IO (Maybe Text)
notAFile file = do
  isFile <- doesFileExist file
  isDir <- doesDirectoryExist file
  pure $
    if
        | isDir -> Just (T.pack file <> " is a directory, not an ST file")
        | not isFile -> Just ("no such file: " <> T.pack file)
        | otherwise -> Nothing

-- | A rejected program as the JSON verdict @run --format json@ prints on
-- standard output: the file and each error with its kind and place.
rejectionJson :: FilePath -> [VerificationError] -> A.Value
rejectionJson file errs =
  A.object
    [ "file" A..= file
    , "verdict" A..= ("rejected" :: Text)
    , "errors" A..= [A.object ["kind" A..= k, "line" A..= l, "column" A..= c, "message" A..= m] | VerificationError k (Pos l c) m <- errs]
    ]

usageError :: String -> Text -> IO ExitCode
usageError cmd msg = do
  hPutStrLn stderr ("stref " <> cmd <> ": " <> T.unpack msg)
  pure (ExitFailure 2)

parseBool :: Text -> Maybe Bool
parseBool t = case T.toUpper t of
  "TRUE" -> Just True
  "FALSE" -> Just False
  "1" -> Just True
  "0" -> Just False
  _ -> Nothing

-- | A value as the command line writes it: TRUE/FALSE, a decimal or 16#
-- integer, or a decimal real.
parseSetting :: Text -> Either Text Setting
parseSetting t0
  | Just b <- parseBool' t = Right (SetBool b)
  | Just h <- T.stripPrefix "16#" (T.filter (/= '_') t), [(n, "")] <- readHex (T.unpack h) = Right (SetInt n)
  | Just n <- readMaybe (T.unpack (T.dropWhile (== '+') t)) = Right (SetInt n)
  | T.any (\c -> c == '.' || c == 'E' || c == 'e') t, all okReal (T.unpack t), Just r <- readMaybe (fixReal (T.unpack t)) = Right (SetReal (double2Float r))
  | otherwise = Left ("'" <> t0 <> "' is not a value (TRUE, FALSE, an integer or a real)")
  where
    t = T.strip t0
    parseBool' x = case T.map toUpper x of
      "TRUE" -> Just True
      "FALSE" -> Just False
      _ -> Nothing
    okReal c = isDigit c || c `elem` ("+-.eE" :: String)
    fixReal s = case s of
      '+' : r -> fixReal r
      '-' : r -> '-' : fixReal r
      '.' : _ -> '0' : s
      _ -> s
    double2Float :: Double -> Float
    double2Float = realToFrac

-- | @%M0010=5@
parseSetArg :: String -> Either Text (Operand, Setting)
parseSetArg arg = case T.breakOn "=" (T.pack arg) of
  (o, v) | not (T.null v) -> do
    operand <- parseOperand o
    s <- parseSetting (T.drop 1 v)
    pure (operand, s)
  _ -> Left ("--set takes OPERAND=VALUE, e.g. %M0010=5, not '" <> T.pack arg <> "'")

-- | "runtime error 2020 (division by zero) at line 4, complements 0 0 0"
describeError :: RuntimeError -> Text
describeError (RuntimeError code line (a, b, c)) =
  "runtime error " <> tshow code <> " (" <> describeErrorCode code <> ") at line " <> tshow line
    <> ", complements " <> T.unwords (map tshow [a, b, c])

tshow :: Show a => a -> Text
tshow = T.pack . show

-- | An operand's contents in its natural reading, with the hex pattern for
-- integer operands.
cellText :: Memory -> Cell -> Text
cellText mem c = case observeOperand mem (op c) of
  VReal r -> T.pack (show r)
  v -> showValue v <> "  (16#" <> hex (readCell mem c) <> ")"
  where
    op = \case
      CellSimple k a -> OpSimple k a
      CellTable k a p -> OpTablePos k a p
    hex :: Word32 -> Text
    hex w = T.justifyRight (cellWidth c `div` 4) '0' (T.toUpper (T.pack (showHex' w)))
    showHex' w = let s = go w "" in if null s then "0" else s
    go 0 acc = acc
    go n acc = go (n `div` 16) ("0123456789abcdef" !! fromIntegral (n `mod` 16) : acc)

-- | JSON for a value: booleans, integers, REAL as a number (or its bits when
-- not finite).
valueJson :: Value -> A.Value
valueJson = \case
  VBool b -> A.Bool b
  VReal r
    | isNaN r || isInfinite r -> A.object ["bits" A..= ("0x" <> T.justifyRight 8 '0' (T.pack (hexW (realBits r))))]
    | otherwise -> A.Number (fromFloatDigits r)
  v -> maybe A.Null (A.Number . fromInteger) (valueToInteger v)
  where
    hexW :: Word32 -> String
    hexW w = if w == 0 then "0" else go w ""
    go 0 acc = acc
    go n acc = go (n `div` 16) ("0123456789ABCDEF" !! fromIntegral (n `mod` 16) : acc)

-- | The command line of an engine given to @--engine@: a name stref has an
-- adapter for (docs/engines.md) is that adapter run as this program, if the
-- engine is installed; anything else is a shell command as it is.
engineCommand :: String -> IO (Either Text String)
engineCommand given = case engineByName (T.pack given) of
  Nothing -> pure (Right given)
  Just e -> do
    found <- findTools e
    case found of
      Left why -> pure (Left why)
      Right _ -> Right <$> adapterCommand e

-- | The shell command that runs an engine's adapter: this program's
-- @adapter@ command.
adapterCommand :: Engine -> IO String
adapterCommand e = do
  self <- getExecutablePath
  pure (quote self <> " adapter " <> T.unpack (engName e))
  where
    quote p = "'" <> concatMap (\c -> if c == '\'' then "'\\''" else [c]) p <> "'"

-- | The trace options of run and eval (docs/trace.md).
data TraceFlags = TraceFlags
  { tfTrace :: Bool
  , tfAll :: Bool
  , tfWatch :: [Text]
  }

traceFlags :: Parser TraceFlags
traceFlags =
  TraceFlags
    <$> switch (long "trace" <> help "Show why each value came out: every statement run, the values read and written, and each rule (with its id and the policy alternative) that decided an outcome; --format json gives one JSON event per line")
    <*> switch (long "trace-all" <> help "With --trace: every iteration of every loop (by default a loop shows its first 3 iterations, then a count)")
    <*> many (T.pack <$> strOption (long "watch" <> metavar "NAME" <> help "A table with a row per cycle and a column for NAME (repeatable: a variable, a path such as MAIN.fb.Q, or an operand); with --trace: only the statements that read or write NAME (V also matches V[2] and V.X)"))

-- | Nothing without tracing; else whether every iteration is kept, and
-- the watched names. --trace-all implies --trace.
traceRequest :: TraceFlags -> Maybe (Bool, [Text])
traceRequest f
  | tfTrace f || tfAll f = Just (tfAll f, tfWatch f)
  | otherwise = Nothing

-- | The names of a watch table: --watch without --trace.
watchTable :: TraceFlags -> [Text]
watchTable f = maybe (tfWatch f) (const []) (traceRequest f)

-- | An error found in the program a snippet was wrapped into, placed in the
-- snippet itself (@stref eval@): the wrapper's lines and columns before the
-- snippet are taken off, also from a position the message names ("the IF
-- at line 1, column 35"); the wrapper's END_PROGRAM, where a block the
-- snippet leaves open is noticed, is the snippet's end.
inSnippet :: Text -> Text -> VerificationError -> VerificationError
inSnippet wrapped snippet e = e {vePos = place (vePos e), veMessage = rewrite (veMessage e)}
  where
    before = fst (T.breakOn snippet wrapped)
    beforeLines = T.count "\n" before
    beforeCol = T.length (snd (T.breakOnEnd "\n" before))
    snippetLines = T.lines snippet
    lastLine = max 1 (length snippetLines)
    endCol = 1 + (if null snippetLines then 0 else T.length (last snippetLines))
    place (Pos l c)
      | l' < 1 = Pos 1 1
      | l' > lastLine = Pos lastLine endCol
      | l' == 1 = Pos 1 (max 1 (c - beforeCol))
      | otherwise = Pos l' c
      where
        l' = l - beforeLines
    rewrite = positions . T.replace "instead of 'END_PROGRAM'" "at the end of the snippet" . endReached
    endReached m = case T.breakOn "'END_PROGRAM' at line" m of
      (a, rest) | not (T.null rest) -> a <> "the end of the snippet" <> snd (T.breakOn " while looking" rest)
      _ -> m
    -- "line L, column C" in a message, as a position of the snippet
    positions m = case T.breakOn "line " m of
      (a, rest)
        | T.null rest -> m
        | Just (l, afterL) <- number (T.drop 5 rest)
        , Just afterComma <- T.stripPrefix ", column " afterL
        , Just (c, afterC) <- number afterComma ->
            let Pos l' c' = place (Pos l c) in a <> "line " <> tshow l' <> ", column " <> tshow c' <> positions afterC
        | otherwise -> a <> "line " <> positions (T.drop 5 rest)
    number t = case T.span isDigit t of
      (ds, r) | not (T.null ds) -> Just (read (T.unpack ds), r)
      _ -> Nothing
    tshow = T.pack . show

-- | The text of a source line (1-based), for a trace; empty outside the file.
sourceLine :: Text -> Int -> Text
sourceLine src l = case drop (l - 1) (T.lines src) of
  x : _ | l >= 1 -> x
  _ -> ""

-- | The last line of @check --portability@.
portabilitySummary :: Int -> String
portabilitySummary n = show n <> " portability warning" <> (if n == 1 then "" else "s") <> " (docs/policies.md explains each policy)"

-- | A program run under several variants (presets, or the alternatives of
-- a policy), side by side: @run --compare@ and @run --presets@.
data Comparison = Comparison
  { cmpVariants :: [Text]
  , cmpUnit :: Text -- ^ what is counted: "cycle" (IEC), "call" (MasterTool XE)
  , cmpCount :: Int
  , cmpFirstParting :: Maybe Int -- ^ the first cycle after which the variants differ
  , cmpErrors :: [Text] -- ^ each variant's error, or "none"
  , cmpRows :: [(Text, [Text])] -- ^ an observed name and its value under each variant
  }

-- | The comparison as text (rows that differ marked @*@, then the first
-- cycle where the variants part) or as one JSON object; exit 0 when they
-- agree after every cycle, 1 when they differ somewhere (as diff does).
printComparison :: Bool -> Comparison -> IO ExitCode
printComparison json c = do
  if json
    then
      BL.putStrLn . A.encode $
        A.object
          [ "variants" .= names
          , "cycles" .= cmpCount c
          , "first_parting_cycle" .= cmpFirstParting c
          , "errors" .= A.object [K.fromText n .= e | (n, e) <- zip names (cmpErrors c)]
          , "vars" .= A.object [K.fromText path .= A.object [K.fromText n .= v | (n, v) <- zip names vs] | (path, vs) <- cmpRows c]
          , "differ" .= [path | (path, vs) <- cmpRows c, differs vs]
          ]
    else do
      TIO.putStrLn ("variants: " <> T.intercalate ", " names <> "; " <> T.pack (show (cmpCount c)) <> " " <> unit <> "s")
      forM_ (zip names (cmpErrors c)) $ \(n, e) -> TIO.putStrLn ("  error under " <> n <> ": " <> e)
      let width = maximum (1 : map (T.length . fst) (cmpRows c))
      forM_ (cmpRows c) $ \(path, vs) ->
        TIO.putStrLn ((if differs vs then "* " else "  ") <> T.justifyLeft width ' ' path <> "  " <> T.intercalate "  " [n <> ": " <> v | (n, v) <- zip names vs])
      TIO.putStrLn $ case (agreeAtEnd, cmpFirstParting c) of
        (True, Nothing) -> "the variants agree after every " <> unit
        (True, Just k) -> "they part after " <> unit <> " " <> T.pack (show k) <> " and agree again after the last"
        (False, Just k) -> "they part after " <> unit <> " " <> T.pack (show k)
        (False, Nothing) -> "they part after a " <> unit <> " beyond the first 1000"
  pure (if cmpFirstParting c == Nothing && agreeAtEnd then ExitSuccess else ExitFailure 1)
  where
    names = cmpVariants c
    unit = cmpUnit c
    differs vs = any (/= head vs) vs
    agreeAtEnd = not (any (differs . snd) (cmpRows c)) && not (differs (cmpErrors c))
