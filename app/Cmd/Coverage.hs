-- | @stref coverage [PATH...]@: every rule of the corpus's RULES indexes with
-- the cases citing it, the testable rules no case cites, and the share of
-- testable rules covered. Exit 1 when a case file is malformed, or with
-- @--strict@ when a testable rule is uncovered; otherwise 0.
module Cmd.Coverage (Cmd.Coverage.command) where

import Control.Monad (forM_, unless)
import qualified Data.Aeson as A
import Data.Aeson ((.=))
import qualified Data.ByteString.Lazy.Char8 as BLC
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Numeric (showFFloat)
import Options.Applicative hiding (command)
import qualified Options.Applicative
import Stref.Conformance.Corpus
import Stref.Conformance.Coverage
import Stref.Conformance.Rules
import System.Exit
import System.IO (stderr)

data Opts = Opts
  { oPaths :: [FilePath]
  , oStrict :: Bool
  , oJson :: Bool
  }

command :: Mod CommandFields (IO ExitCode)
command =
  Options.Applicative.command
    "coverage"
    ( info
        (run <$> opts)
        (progDesc "Show which catalogue rules the conformance corpus covers")
    )
  where
    opts =
      Opts
        <$> many (strArgument (metavar "PATH..." <> help "Corpus directories or case files (default: conformance)"))
        <*> switch (long "strict" <> help "Exit 1 when a testable rule is not covered")
        <*> switch (long "json" <> help "Print the coverage as JSON")

run :: Opts -> IO ExitCode
run o = do
  corpus <- loadCorpus (if null (oPaths o) then ["conformance"] else oPaths o)
  let cases = [c | Loaded c <- corpusEntries corpus]
      invalid = [e | Invalid _ _ e <- corpusEntries corpus]
      rcs = coverage (corpusRules corpus) cases
      missing = uncoveredTestable rcs
      (covered, testable) = coveredFraction rcs
      pct :: Double
      pct = if testable == 0 then 100 else 100 * fromIntegral covered / fromIntegral testable
      summary = T.pack ("coverage: " <> show covered <> "/" <> show testable <> " testable rules (" <> showFFloat (Just 1) pct "" <> "%)")
  mapM_ (TIO.hPutStrLn stderr) (corpusErrors corpus ++ invalid)
  if oJson o
    then
      BLC.putStrLn . A.encode $
        A.object
          [ "rules"
              .= [ A.object
                     [ "dialect" .= rcDialect rc
                     , "id" .= ruleId (rcRule rc)
                     , "title" .= ruleTitle (rcRule rc)
                     , "untestable" .= ruleUntestable (rcRule rc)
                     , "cases" .= rcCases rc
                     ]
                 | rc <- rcs
                 ]
          , "uncovered" .= map (ruleId . rcRule) missing
          , "covered" .= covered
          , "testable" .= testable
          ]
    else do
      forM_ rcs $ \rc -> do
        let r = rcRule rc
            status = case (ruleUntestable r, rcCases rc) of
              (_, cs@(_ : _)) -> T.pack (show (length cs)) <> " case(s): " <> T.intercalate ", " cs
              (Just why, []) -> "untestable: " <> why
              (Nothing, []) -> "UNCOVERED"
        TIO.putStrLn (rcDialect rc <> " " <> ruleId r <> " | " <> ruleTitle r <> " | " <> status)
      unless (null missing) $ do
        TIO.putStrLn ""
        TIO.putStrLn ("uncovered testable rules (" <> T.pack (show (length missing)) <> "): " <> T.intercalate ", " (map (ruleId . rcRule) missing))
      TIO.putStrLn summary
  pure $
    if not (null invalid) || not (null (corpusErrors corpus)) || (oStrict o && not (null missing))
      then ExitFailure 1
      else ExitSuccess
