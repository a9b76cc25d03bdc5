-- | @stref eval SNIPPET@: run a few statements (optionally preceded by VAR
-- blocks) or a bare expression, wrapped into a PROGRAM; print every
-- variable's final value and INTERNAL_OVERFLOW, or the expression's value
-- and type. With @--compare POLICY@ the snippet runs under every alternative
-- of that policy and the results are shown side by side.
module Cmd.Eval (command) where

import Data.List (nub)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Options.Applicative hiding (command)
import qualified Options.Applicative as O
import System.Exit
import System.IO (stderr)
import Cmd.Common
import Cmd.Iec (dialectPolicies, evalIec, evalIecRows, evalIecTrace, isIecDialect, oneStatementALine)
import Stref.Diagnostics (RuntimeError (..))
import Stref.Execution
import Stref.Policy
import Stref.Run
import Stref.Types (typeName)
import Stref.Values
import Stref.Trace (Item, items, parting, renderText, watching)

data Options = Options
  { optSnippet :: String
  , optCompare :: Maybe String
  , optPolicies :: [String]
  , optDialect :: String
  , optCalls :: Int
  , optTrace :: TraceFlags
  }

command :: Mod CommandFields (IO ExitCode)
command =
  O.command "eval" $
    info
      (run <$> options)
      ( progDesc "Run ST statements (with optional VAR ... END_VAR blocks first) or a bare expression; print the variables and INTERNAL_OVERFLOW, or the value and type. Exit 0, 1 for a rejected snippet or a runtime error, 2 for a usage error"
      )

options :: Parser Options
options =
  Options
    <$> strArgument (metavar "SNIPPET" <> help "e.g. 'VAR I : INT; END_VAR I := 32767 + 1;' or '7 / 2' (write -- before a snippet that starts with -)")
    <*> optional (strOption (long "compare" <> metavar "POLICY" <> help "Run under every alternative of POLICY and show the results side by side"))
    <*> many (strOption (long "policy" <> metavar "K=V" <> help "Set a policy, e.g. overflow=wrap"))
    <*> strOption (long "dialect" <> metavar "NAME" <> value "mastertool-xe" <> showDefault <> help "The dialect: mastertool-xe, tecomat or nexto (an IEC dialect runs the snippet as the body of PROGRAM MAIN)")
    <*> option auto (long "calls" <> metavar "N" <> value 1 <> showDefault <> help "The number of scan cycles (IEC dialects) or module calls (MasterTool XE: the operands a snippet maps keep their values, its locals start again)")
    <*> traceFlags

-- | One run's observable outcome, as lines of (label, value).
data Observed = Observed
  { obRows :: [(Text, Text)]
  , obFailed :: Bool
  }

-- | The full error description, or a compact one for tables.
observe :: Bool -> SnippetResult -> Observed
observe full sr =
  Observed (valueRows ++ [("INTERNAL_OVERFLOW", showValue (VBool (crOverflow r))), ("error", maybe "none" errText (crError r))]) (crError r /= Nothing)
  where
    r = srResult sr
    valueRows = case srType sr of
      Just t ->
        [ (if isResult n then "value" else n, showValue v <> if isResult n then " : " <> typeName t else "")
        | (n, v) <- crVars r
        , isResult n
        ]
      Nothing -> [(dropProgram n, showValue v) | (n, v) <- crVars r]
    errText e@(RuntimeError code line _)
      | full = describeError e
      | otherwise = T.pack (show code) <> " at line " <> T.pack (show line)
    isResult n = "EVAL_RESULT" `T.isSuffixOf` n
    dropProgram n = maybe n id (T.stripPrefix "EVAL." n)

run :: Options -> IO ExitCode
run o = case dialectPolicies (optDialect o) (optPolicies o) of
  Left msg -> usageError "eval" msg
  Right pol | isIecDialect pol -> case optCompare o of
    Nothing -> evalIec pol (T.pack (optSnippet o)) (optCalls o) (traceRequest (optTrace o))
    Just name -> case alternativesOf (T.pack name) pol of
      Left msg -> usageError "eval" msg
      Right alts | Just _ <- traceRequest (optTrace o) -> do
        let traces = [(alt, p, evalIecTrace p (T.pack (optSnippet o)) (optCalls o)) | (alt, p) <- alts]
        case [(alt, p, src, its) | (alt, p, Just (src, its)) <- traces] of
          ran@((_, _, src, _) : _) -> do
            mapM_ TIO.putStrLn (compareTraces (T.pack name) (sourceLine src) [(alt, p, its) | (alt, p, _, its) <- ran])
            pure ExitSuccess
          [] -> usageError "eval" "the snippet is rejected under every alternative"
      Right alts -> do
        let cols = [(alt, (\rows -> Observed rows False) <$> evalIecRows p (T.pack (optSnippet o)) (optCalls o)) | (alt, p) <- alts]
        TIO.putStr (sideBySide (T.pack name) cols)
        pure (if all ((== Nothing) . fmap obRows . snd) cols then ExitFailure 1 else ExitSuccess)
  Right _ -> runMasterTool o

runMasterTool :: Options -> IO ExitCode
runMasterTool o = case applyPolicies (optPolicies o) of
  Left msg -> usageError "eval" msg
  Right _ | optCalls o < 1 -> usageError "eval" "--calls takes a number of module calls from 1 (the result is the last call's)"
  Right pol -> case optCompare o of
    Nothing
      | Just (everyIteration, watched) <- traceRequest (optTrace o) -> case evalSnippetTraced everyIteration (optCalls o) pol (oneStatementALine snippet) of
          Left (src, failure) -> rejected src failure
          Right (sr, events) -> do
            mapM_ TIO.putStrLn (renderText pol (sourceLine (snSource (srSnippet sr))) (watching watched (items events)))
            shown sr
    Nothing -> case evalSnippetCalls (optCalls o) pol snippet of
      Left (src, failure) -> rejected src failure
      Right sr -> shown sr
    Just name -> case alternativesOf (T.pack name) pol of
      Left msg -> usageError "eval" msg
      Right alts | Just (everyIteration, watched) <- traceRequest (optTrace o) -> do
        -- each alternative's trace from the first item where they part
        let runs = [(alt, p, evalSnippetTraced everyIteration (optCalls o) p (oneStatementALine snippet)) | (alt, p) <- alts]
        case [(alt, p, snSource (srSnippet sr), watching watched (items events)) | (alt, p, Right (sr, events)) <- runs] of
          ran@((_, _, src, _) : _) -> do
            mapM_ TIO.putStrLn (compareTraces (T.pack name) (sourceLine src) [(alt, p, its) | (alt, p, _, its) <- ran])
            pure ExitSuccess
          [] -> case [(src, f) | (_, _, Left (src, f)) <- runs] of
            (src, f) : _ -> rejected src f
            [] -> usageError "eval" ("the policy " <> T.pack name <> " has no alternatives")
      Right alts -> do
        let runs = [(alt, evalSnippetCalls (optCalls o) p snippet) | (alt, p) <- alts]
        case [(src, f) | (_, Left (src, f)) <- runs] of
          (src, f) : _ | all (isLeft . snd) runs -> rejected src f
          _ -> do
            TIO.putStr (sideBySide (T.pack name) [(alt, either (const Nothing) (Just . observe False) res) | (alt, res) <- runs])
            pure ExitSuccess
  where
    snippet = T.pack (optSnippet o)
    shown sr = do
      let ob = observe True sr
      mapM_ (\(k, v) -> TIO.putStrLn (k <> " = " <> v)) (obRows ob)
      pure (if obFailed ob then ExitFailure 1 else ExitSuccess)
    isLeft = either (const True) (const False)
    -- the errors placed in the snippet as it went into the wrapper
    rejected src failure = do
      let written = if traceRequest (optTrace o) /= Nothing then oneStatementALine snippet else snippet
          placed = case failure of
            SyntaxError e -> SyntaxError (inSnippet src written e)
            Rejected es -> Rejected (map (inSnippet src written) es)
            other -> other
      TIO.hPutStr stderr (renderRunFailure "<snippet>" written placed)
      pure (ExitFailure 1)

-- | @eval --compare POLICY --trace@: the traces up to the first item where
-- the alternatives part (the last few shared items, for context), then
-- each alternative's trace from there.
compareTraces :: Text -> (Int -> Text) -> [(Text, Policies, [Item])] -> [Text]
compareTraces policy source runs = case parting [its | (_, _, its) <- runs] of
  Nothing -> ["the traces under every alternative of " <> policy <> " are the same"]
  Just k ->
    let (_, p0, its0) = head runs
        shared = take k its0
     in ( if k == 0
            then ["the alternatives of " <> policy <> " part at the first trace item"]
            else
              ["the alternatives of " <> policy <> " agree on the first " <> T.pack (show k) <> " trace items; the last ones:"]
                ++ map ("  " <>) (renderText p0 source (drop (k - contextItems) shared))
        )
          ++ concat
            [ "" : ("under " <> policy <> "=" <> alt <> ":") : map ("  " <>) (renderText p source (take shownItems (drop k its)))
            | (alt, p, its) <- runs
            ]
  where
    contextItems = 3
    shownItems = 6

-- | A table: one column per alternative, one row per observed item; rows
-- whose values differ are marked with @*@.
sideBySide :: Text -> [(Text, Maybe Observed)] -> Text
sideBySide policy cols =
  T.unlines (header : rule : map row labels)
  where
    labels = nub (concat [map fst (obRows ob) | (_, Just ob) <- cols])
    cell label = \case
      Nothing -> "(rejected)"
      Just ob -> maybe "-" id (lookup label (obRows ob))
    width = maximum (map T.length (policy : labels)) + 2
    colWidth = maximum (12 : [T.length (cell l c) | l <- labels, (_, c) <- cols] ++ [T.length a | (a, _) <- cols]) + 2
    header = "  " <> T.justifyLeft width ' ' policy <> T.concat [T.justifyLeft colWidth ' ' a | (a, _) <- cols]
    rule = "  " <> T.replicate (width + colWidth * length cols) "-"
    row l =
      let vals = [cell l c | (_, c) <- cols]
          mark = if length (nub vals) > 1 then "* " else "  "
       in mark <> T.justifyLeft width ' ' l <> T.concat [T.justifyLeft colWidth ' ' v | v <- vals]
