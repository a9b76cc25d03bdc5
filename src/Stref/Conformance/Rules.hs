-- | The rule index of a dialect's corpus (@conformance/<dialect>/RULES@):
-- one rule per line, @ID | title@ or @ID | title | untestable: reason@;
-- @#@ comments and blank lines are ignored. Cases may cite only these ids.
module Stref.Conformance.Rules
  ( Rule (..)
  , parseRules
  , rulesFileName
  ) where

import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T

data Rule = Rule
  { ruleId :: Text
  , ruleTitle :: Text
  , ruleUntestable :: Maybe Text -- ^ the reason, for a rule no case can check
  , ruleLine :: Int
  }
  deriving (Eq, Show)

rulesFileName :: FilePath
rulesFileName = "RULES"

-- | Every malformed line is reported as @file:line: message@.
parseRules :: FilePath -> Text -> Either [Text] [Rule]
parseRules file txt =
  case (errors, dupErrors) of
    ([], []) -> Right rules
    _ -> Left (errors ++ dupErrors)
  where
    parsed = [(n, parseLine n l) | (n, l) <- zip [1 ..] (T.lines txt), not (skip l)]
    skip l = let s = T.strip l in T.null s || "#" `T.isPrefixOf` s
    errors = [e | (_, Left e) <- parsed]
    rules = [r | (_, Right r) <- parsed]
    dupErrors = duplicates S.empty rules
    duplicates _ [] = []
    duplicates seen (r : rs)
      | ruleId r `S.member` seen = at (ruleLine r) ("rule " <> ruleId r <> " is listed twice") : duplicates seen rs
      | otherwise = duplicates (S.insert (ruleId r) seen) rs
    at :: Int -> Text -> Text
    at n msg = T.pack file <> ":" <> T.pack (show n) <> ": " <> msg
    parseLine n l = case map T.strip (T.splitOn "|" l) of
      [i, title] -> rule n i title Nothing
      [i, title, extra]
        | Just reason <- T.stripPrefix "untestable:" extra -> rule n i title (Just (T.strip reason))
        | otherwise -> Left (at n "the third field must read 'untestable: <reason>'")
      _ -> Left (at n "expected 'ID | title' or 'ID | title | untestable: reason'")
    rule n i title u
      | T.null i || T.any (\c -> c == ' ' || c == '\t') i = Left (at n ("'" <> i <> "' is not a rule id"))
      | T.null title = Left (at n ("rule " <> i <> " has no title"))
      | otherwise = Right (Rule i title u n)
