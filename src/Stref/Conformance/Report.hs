-- | Reports of a conformance run: text for people, JSON for tools (its
-- format is documented in conformance/README.md), JUnit XML for CI servers.
module Stref.Conformance.Report
  ( Totals (..)
  , totals
  , outcomeName
  , failing
  , summaryLine
  , groupTotals
  , TextOptions (..)
  , textReport
  , jsonReport
  , totalsJson
  , junitReport
  ) where

import Data.Aeson (Value, object, (.=))
import qualified Data.Aeson as A
import qualified Data.ByteString.Lazy as BL
import Data.List (foldl')
import qualified Data.List.NonEmpty as NE
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import Numeric (showFFloat)
import Stref.Conformance.Case
import Stref.Conformance.Corpus (areaOfId)
import Stref.Conformance.Runner

data Totals = Totals
  { tPassed :: !Int
  , tFailed :: !Int
  , tUnsupported :: !Int
  , tEngineError :: !Int
  , tSkipped :: !Int
  }
  deriving (Eq, Show)

instance Semigroup Totals where
  Totals a b c d e <> Totals a' b' c' d' e' = Totals (a + a') (b + b') (c + c') (d + d') (e + e')

instance Monoid Totals where
  mempty = Totals 0 0 0 0 0

-- | The result names of the contract; a malformed case counts as failed.
outcomeName :: Outcome -> Text
outcomeName = \case
  Pass -> "pass"
  Fail _ -> "fail"
  InvalidCase _ -> "fail"
  Unsupported _ -> "unsupported"
  EngineError _ -> "engine-error"
  Skipped _ -> "skipped"

count1 :: Outcome -> Totals
count1 = \case
  Pass -> Totals 1 0 0 0 0
  Fail _ -> Totals 0 1 0 0 0
  InvalidCase _ -> Totals 0 1 0 0 0
  Unsupported _ -> Totals 0 0 1 0 0
  EngineError _ -> Totals 0 0 0 1 0
  Skipped _ -> Totals 0 0 0 0 1

totals :: [CaseResult] -> Totals
totals = foldMap (count1 . resOutcome)

-- | Does the result make the run fail? (Known failures are already
-- skipped; unsupported is an engine's declared limit, not a failure.)
failing :: CaseResult -> Bool
failing r = case resOutcome r of
  Fail _ -> True
  InvalidCase _ -> True
  EngineError _ -> True
  _ -> False

-- | The last line of every text report.
summaryLine :: Totals -> Text
summaryLine t =
  T.pack (show (tPassed t)) <> " passed, " <> T.pack (show (tFailed t)) <> " failed, "
    <> T.pack (show (tUnsupported t)) <> " unsupported, " <> T.pack (show (tEngineError t)) <> " engine-error, "
    <> T.pack (show (tSkipped t)) <> " skipped"

-- | Totals per group; a case counts once in each group it belongs to.
groupTotals :: (CaseResult -> [Text]) -> [CaseResult] -> M.Map Text Totals
groupTotals keys = foldl' add M.empty
  where
    add m r = foldl' (\acc k -> M.insertWith (<>) k (count1 (resOutcome r)) acc) m (keys r)

dialectOf, areaOf, rulesOf, featuresOf :: CaseResult -> [Text]
dialectOf r = [maybe (T.takeWhile (/= '/') (resId r)) caseDialect (resCase r)]
areaOf r = [maybe (areaOfId (resId r)) (\c -> caseDialect c <> "/" <> caseArea c) (resCase r)]
rulesOf r = maybe [] caseRules (resCase r)
featuresOf r = maybe [] caseFeatures (resCase r)

-- | One line: for a failure, its first difference.
detail :: Outcome -> Text
detail = \case
  Pass -> ""
  Fail ds -> differenceText (NE.head ds)
  InvalidCase e -> e
  Unsupported e -> e
  EngineError e -> e
  Skipped e -> e

-- | What the text report shows.
data TextOptions = TextOptions
  { toVerbose :: Bool -- ^ list every case, and the totals of every rule and feature
  , toOnlyFailures :: Bool -- ^ list only the cases that fail the run (fail, engine-error, invalid)
  , toRuleTitles :: M.Map Text Text -- ^ rule id → title, from the RULES indexes
  }

-- | One line per case that did not pass (filtered-out cases are only
-- counted; with 'toVerbose' every case is listed, with 'toOnlyFailures'
-- only those that fail the run), each further difference of a failure and
-- the rules a failing case cites on lines of their own, then the totals
-- per dialect, area, rule and feature (rules and features only where a
-- case did not pass, unless verbose), and the summary line last.
textReport :: TextOptions -> [CaseResult] -> Text
textReport opts rs =
  T.unlines $
    concatMap caseLines rs
      ++ section True "by dialect" dialectOf
      ++ section True "by area" areaOf
      ++ section verbose "by rule" rulesOf
      ++ section verbose "by feature" featuresOf
      ++ [summaryLine (totals rs)]
  where
    verbose = toVerbose opts
    caseLines r
      | toOnlyFailures opts && not (failing r) = []
      | otherwise = caseLine r ++ (if failing r then map ruleLine (rulesOf r) else []) ++ (if verbose then exchangeLines r else [])
    -- what an external engine was asked and answered, for a case it failed
    exchangeLines r = case resExchange r of
      Nothing -> []
      Just x -> ["  request: " <> xcRequest x, "  answer: " <> maybe "none" T.strip (xcAnswer x)]
    ruleLine i = "  rule " <> i <> maybe "" (": " <>) (M.lookup i (toRuleTitles opts))
    caseLine r = case resOutcome r of
      Pass -> ["PASS " <> resId r | verbose]
      Skipped why
        | resKnownFailure r || verbose -> ["SKIP " <> resId r <> ": " <> why]
        | otherwise -> []
      InvalidCase e -> ["INVALID " <> e]
      o@(Fail ds) -> ("FAIL " <> resId r <> ": " <> detail o) : ["  " <> differenceText d | d <- NE.tail ds]
      o -> [T.toUpper (outcomeName o) <> " " <> resId r <> ": " <> detail o]
    -- rules and features are many: without @verbose@ only those with a
    -- case that did not pass are listed
    section full title keys =
      let m = groupTotals keys rs
          shown = [(k, t) | (k, t) <- M.toList m, full || troubled t]
          hidden = M.size m - length shown
          note = if hidden > 0 then " (" <> T.pack (show hidden) <> " where every case passed or was skipped are not listed; --verbose lists them)" else ""
       in if M.null m then [] else ("" : (title <> note <> ":") : [("  " <> k <> ": " <> summaryLine t) | (k, t) <- shown])
    troubled t = tFailed t + tUnsupported t + tEngineError t > 0

totalsJson :: Totals -> Value
totalsJson t =
  object
    [ "passed" .= tPassed t
    , "failed" .= tFailed t
    , "unsupported" .= tUnsupported t
    , "engine-error" .= tEngineError t
    , "skipped" .= tSkipped t
    ]

-- | The JSON report (conformance/README.md, "JSON report").
jsonReport :: Text -> [(Text, Text)] -> [CaseResult] -> BL.ByteString
jsonReport engine policies rs =
  A.encode $
    object
      [ "protocol" .= ("stref-engine/1" :: Text)
      , "engine" .= engine
      , "policies" .= M.fromList policies
      , "cases" .= map caseJson rs
      , "totals" .= totalsJson (totals rs)
      , "by_dialect" .= fmap totalsJson (groupTotals dialectOf rs)
      , "by_area" .= fmap totalsJson (groupTotals areaOf rs)
      , "by_rule" .= fmap totalsJson (groupTotals rulesOf rs)
      , "by_feature" .= fmap totalsJson (groupTotals featuresOf rs)
      ]
  where
    differenceJson d = object ["what" .= dWhat d, "expected" .= dExpected d, "actual" .= dActual d]
    caseJson r =
      object
        [ "id" .= resId r
        , "file" .= resFile r
        , "result" .= outcomeName (resOutcome r)
        , "detail" .= detail (resOutcome r)
        , "difference" .= case resOutcome r of
            Fail ds -> differenceJson (NE.head ds)
            _ -> A.Null
        , "differences" .= case resOutcome r of
            Fail ds -> map differenceJson (NE.toList ds)
            _ -> []
        , "invalid" .= case resOutcome r of
            InvalidCase _ -> True
            _ -> False
        , "known_failure" .= resKnownFailure r
        , "rules" .= rulesOf r
        , "features" .= featuresOf r
        , "seconds" .= resSeconds r
        ]

-- | JUnit XML: one testsuite per area, one testcase per case (classname the
-- area with dots, name the case's slug); fail → @failure@, engine-error and
-- malformed cases → @error@, unsupported and skipped → @skipped@. The
-- @message@ attribute holds the first difference or the error; the
-- element's text the case's description, file and rules (with their titles)
-- and every difference, so that a CI page shows what to look at.
junitReport :: M.Map Text Text -> [CaseResult] -> BL.ByteString
junitReport titles rs =
  BL.fromStrict . TE.encodeUtf8 . T.unlines $
    ["<?xml version=\"1.0\" encoding=\"UTF-8\"?>", "<testsuites name=\"stref conformance\"" <> counts rs <> ">"]
      ++ concatMap suite (M.toList bySuite)
      ++ ["</testsuites>"]
  where
    bySuite = M.fromListWith (flip (++)) [(head' (areaOf r), [r]) | r <- rs]
    head' = \case
      (x : _) -> x
      [] -> ""
    counts xs =
      let t = totals xs
          errors = tEngineError t + length [() | r <- xs, InvalidCase _ <- [resOutcome r]]
          failures = tFailed t - length [() | r <- xs, InvalidCase _ <- [resOutcome r]]
       in attr "tests" (length xs) <> attr "failures" failures <> attr "errors" errors
            <> attr "skipped" (tSkipped t + tUnsupported t) <> " time=\"" <> secs (sum (map resSeconds xs)) <> "\""
    attr :: Text -> Int -> Text
    attr k v = " " <> k <> "=\"" <> T.pack (show v) <> "\""
    secs s = T.pack (showFFloat (Just 3) s "")
    suite (name, xs) =
      ["  <testsuite name=\"" <> esc name <> "\"" <> counts xs <> ">"]
        ++ concatMap testcase xs
        ++ ["  </testsuite>"]
    testcase r =
      let slug = T.takeWhileEnd (/= '/') (resId r)
          classname = T.replace "/" "." (T.dropEnd (T.length slug + 1) (resId r))
          open = "    <testcase name=\"" <> esc slug <> "\" classname=\"" <> esc classname <> "\" time=\"" <> secs (resSeconds r) <> "\""
          child tag msg body = [open <> ">", "      <" <> tag <> " message=\"" <> esc (T.take 200 msg) <> "\">" <> esc (T.intercalate "\n" body) <> "</" <> tag <> ">", "    </testcase>"]
          about =
            ["description: " <> caseDescription c | Just c <- [resCase r]]
              ++ ["file: " <> T.pack (resFile r)]
              ++ ["rule " <> i <> maybe "" (": " <>) (M.lookup i titles) | i <- rulesOf r]
       in case resOutcome r of
            Pass -> [open <> "/>"]
            o@(Fail ds) -> child "failure" (detail o) (about ++ map differenceText (NE.toList ds))
            o@(InvalidCase _) -> child "error" ("invalid case: " <> detail o) (about ++ [detail o])
            o@(EngineError _) -> child "error" ("engine-error: " <> detail o) (about ++ ["engine-error: " <> detail o])
            o@(Unsupported _) -> [open <> ">", "      <skipped message=\"" <> esc ("unsupported: " <> detail o) <> "\"/>", "    </testcase>"]
            o@(Skipped _) -> [open <> ">", "      <skipped message=\"" <> esc (detail o) <> "\"/>", "    </testcase>"]
    esc = T.concatMap $ \case
      '<' -> "&lt;"
      '>' -> "&gt;"
      '&' -> "&amp;"
      '"' -> "&quot;"
      '\'' -> "&apos;"
      c
        | c < ' ' && c `notElem` ("\n\t" :: String) -> "?"
        | otherwise -> T.singleton c
