-- | Merging the reports of a corpus run split into shards
-- (@stref conformance --shard I/N@, one machine or CI job per shard) into
-- the report of the whole run (@stref report merge@): JSON reports into a
-- JSON report, JUnit XML reports into a JUnit XML report, each of the same
-- format as @stref conformance@ writes (conformance/README.md).
--
-- The shards of one run are disjoint, so the merge is the union of their
-- cases in case-id order; the totals are recomputed from the cases' results
-- and the groups (@by_dialect@, @by_area@, @by_rule@, @by_feature@; JUnit's
-- test suites) are the sums of the shards'. What legitimately differs from
-- the report of an unsharded run is only the time taken: each case's
-- @seconds@ (JSON) or @time@ (JUnit; a suite's and the whole run's time are
-- the sums of their cases' times as the shards wrote them, to the
-- millisecond).
module Stref.Conformance.Merge
  ( ReportFormat (..)
  , detectFormat
  , mergeJson
  , mergeJunit
  ) where

import Control.Monad (foldM, forM, unless, when)
import Data.Aeson (Value (..), object, (.=))
import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Char (isSpace)
import qualified Data.Map.Strict as M
import Data.Scientific (toBoundedInteger)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Vector as V
import Numeric (showFFloat)
import Stref.Conformance.Report (Totals (..), totalsJson)
import Text.Read (readMaybe)

data ReportFormat = JsonReport | JunitReport
  deriving (Eq, Show)

-- | The format of a report, from its first non-blank character: @{@ is a
-- JSON report, @<@ a JUnit XML report; anything else is no report of
-- @stref conformance --format json|junit@ (a text report, another file).
detectFormat :: BL.ByteString -> Maybe ReportFormat
detectFormat b = case BLC.uncons (BLC.dropWhile isSpace b) of
  Just ('{', _) -> Just JsonReport
  Just ('<', _) -> Just JunitReport
  _ -> Nothing

-- * JSON

-- | A JSON report as read: its file, the fields every shard of a run
-- shares, its cases by id, its groups.
data JsonShard = JsonShard
  { jsFile :: FilePath
  , jsShared :: [(Text, Value)]
  , jsCases :: [(Text, Value)]
  , jsGroups :: [(Text, M.Map Text Totals)]
  }

sharedFields, groupFields :: [Text]
sharedFields = ["protocol", "engine", "policies"]
groupFields = ["by_dialect", "by_area", "by_rule", "by_feature"]

-- | Merge JSON reports (each with the file it came from, for messages)
-- into one report and its totals. 'Left' says why they cannot be merged:
-- a file that is no JSON report, reports of different runs (protocol,
-- engine or policies differ), a case in two reports (shards that overlap,
-- or one report given twice), totals that do not match the cases.
mergeJson :: [(FilePath, BL.ByteString)] -> Either Text (BL.ByteString, Totals)
mergeJson inputs = do
  shards <- mapM readShard inputs
  case shards of
    [] -> Left "no report to merge"
    first : rest -> do
      mapM_ (sameRun first) rest
      cases <- foldM addCases M.empty shards
      let merged = M.elems cases
      total <- mconcat <$> mapM (uncurry caseTotals) merged
      let groups = [(g, M.unionsWith (<>) [m | s <- shards, Just m <- [lookup g (jsGroups s)]]) | g <- groupFields]
          report =
            object $
              [K.fromText k .= v | (k, v) <- jsShared first]
                ++ [ "cases" .= map snd merged
                   , "totals" .= totalsJson total
                   ]
                ++ [K.fromText g .= fmap totalsJson m | (g, m) <- groups]
      pure (A.encode report <> "\n", total)
  where
    addCases acc s =
      foldM
        ( \m (i, c) -> case M.lookup i m of
            Just (other, _) -> Left (overlap i other (jsFile s))
            Nothing -> Right (M.insert i (jsFile s, c) m)
        )
        acc
        (jsCases s)
    sameRun a b =
      forM_' sharedFields $ \k ->
        when (lookup k (jsShared a) /= lookup k (jsShared b)) $
          Left (T.pack (jsFile b) <> ": its " <> k <> " differs from that of " <> T.pack (jsFile a) <> "; only the shards of one run (the same engine, policies and protocol) can be merged")
    forM_' xs f = mapM_ f xs

overlap :: Text -> FilePath -> FilePath -> Text
overlap i a b
  | a == b = "the case " <> i <> " is reported twice in " <> T.pack a
  | otherwise = "the case " <> i <> " is in both " <> T.pack a <> " and " <> T.pack b <> "; the reports of disjoint shards (--shard I/N of one N) can be merged, not overlapping runs"

readShard :: (FilePath, BL.ByteString) -> Either Text JsonShard
readShard (file, bytes) = do
  o <- case A.eitherDecode bytes of
    Right (Object o) -> Right o
    Right _ -> notReport "it is JSON but not an object"
    Left e -> notReport ("it is not valid JSON: " <> T.pack e)
  let field k = maybe (notReport ("it has no field " <> k)) Right (KM.lookup (K.fromText k) o)
  shared <- forM sharedFields $ \k -> (k,) <$> field k
  cases <- field "cases" >>= \case
    Array xs -> forM (V.toList xs) $ \case
      c@(Object co) | Just (String i) <- KM.lookup "id" co -> Right (i, c)
      _ -> notReport "a case has no id"
    _ -> notReport "its cases are not a list"
  groups <- forM groupFields $ \g -> field g >>= \case
    Object m -> (g,) . M.fromList <$> mapM (\(k, v) -> (K.toText k,) <$> totalsOf (file <> ": " <> T.unpack g) v) (KM.toList m)
    _ -> notReport (g <> " is not an object")
  stated <- field "totals" >>= totalsOf file
  counted <- mconcat <$> mapM (caseTotals file . snd) cases
  unless (stated == counted) $
    Left (T.pack file <> ": its totals do not match its cases (" <> T.pack (show (length cases)) <> " cases); an edited or truncated report?")
  pure (JsonShard file shared cases groups)
  where
    notReport why = Left (T.pack file <> " is not a JSON report of stref conformance --format json: " <> why)

-- | A group's (or the run's) counts.
totalsOf :: FilePath -> Value -> Either Text Totals
totalsOf what = \case
  Object o -> do
    let n k = case KM.lookup k o of
          Just (Number x) | Just i <- toBoundedInteger x, i >= 0 -> Right i
          _ -> Left (T.pack what <> ": a count " <> K.toText k <> " is missing or not a count")
    Totals <$> n "passed" <*> n "failed" <*> n "unsupported" <*> n "engine-error" <*> n "skipped"
  _ -> Left (T.pack what <> ": totals that are not an object")

-- | What one case adds to the totals: its @result@ counted.
caseTotals :: FilePath -> Value -> Either Text Totals
caseTotals file = \case
  Object o | Just (String r) <- KM.lookup "result" o -> case r of
    "pass" -> Right (Totals 1 0 0 0 0)
    "fail" -> Right (Totals 0 1 0 0 0)
    "unsupported" -> Right (Totals 0 0 1 0 0)
    "engine-error" -> Right (Totals 0 0 0 1 0)
    "skipped" -> Right (Totals 0 0 0 0 1)
    _ -> Left (T.pack file <> ": the result " <> r <> " is none of pass, fail, unsupported, engine-error, skipped")
  _ -> Left (T.pack file <> ": a case without a result")

-- * JUnit XML

-- | One @<testcase>@ as written: its lines, its key (the case id rebuilt
-- from classname and name, for the order), what it counts as, its time.
data TestCase = TestCase
  { tcKey :: Text
  , tcLines :: [Text]
  , tcKind :: Kind
  , tcTime :: Double
  }

data Kind = KPass | KFailure | KError | KSkipped
  deriving (Eq)

-- | Merge JUnit XML reports of @stref conformance --format junit@ into one
-- (its totals: passed, failed, unsupported and skipped together as JUnit
-- counts them, engine errors with malformed cases). The files are read as
-- stref writes them, one element a line; 'Left' for anything else, or for
-- a test case in two reports.
mergeJunit :: [(FilePath, Text)] -> Either Text (Text, (Int, Int, Int, Int))
mergeJunit inputs = do
  suites <- concat <$> mapM readJunit inputs
  bySuite <-
    foldM
      ( \m (file, name, cases) -> do
          let old = M.findWithDefault M.empty name m
          new <- foldM (\acc (f, tc) -> maybe (Right (M.insert (tcKey tc) (f, tc) acc)) (\(other, _) -> Left (overlap (tcKey tc) other f)) (M.lookup (tcKey tc) acc)) old [(file, c) | c <- cases]
          pure (M.insert name new m)
      )
      M.empty
      suites
  let all' = concatMap (map snd . M.elems) (M.elems bySuite)
      out =
        ["<?xml version=\"1.0\" encoding=\"UTF-8\"?>", "<testsuites name=\"stref conformance\"" <> counts all' <> ">"]
          ++ concat
            [ ["  <testsuite name=\"" <> name <> "\"" <> counts cs <> ">"] ++ concatMap tcLines cs ++ ["  </testsuite>"]
            | (name, m) <- M.toList bySuite
            , let cs = map snd (M.elems m)
            ]
          ++ ["</testsuites>"]
      n k = length (filter ((== k) . tcKind) all')
  pure (T.unlines out, (length all', n KFailure, n KError, n KSkipped))
  where
    counts cs =
      let n k = T.pack (show (length (filter ((== k) . tcKind) cs)))
       in " tests=\"" <> T.pack (show (length cs)) <> "\" failures=\"" <> n KFailure <> "\" errors=\"" <> n KError
            <> "\" skipped=\"" <> n KSkipped <> "\" time=\"" <> T.pack (showFFloat (Just 3) (sum (map tcTime cs)) "") <> "\""

-- | The suites of one JUnit report: (file, suite name as written, cases).
readJunit :: (FilePath, Text) -> Either Text [(FilePath, Text, [TestCase])]
readJunit (file, text) = case dropWhile T.null (map (T.dropWhileEnd (== '\r')) (T.lines text)) of
  decl : top : rest
    | "<?xml" `T.isPrefixOf` decl
    , "<testsuites " `T.isPrefixOf` top ->
        suitesOf (dropWhileEnd' T.null rest)
  _ -> notReport "it does not start with <?xml ...?> and <testsuites ...>"
  where
    notReport why = Left (T.pack file <> " is not a JUnit report of stref conformance --format junit: " <> why)
    dropWhileEnd' p = reverse . dropWhile p . reverse
    suitesOf = \case
      ["</testsuites>"] -> Right []
      l : ls
        | Just name <- attribute "name" l
        , "  <testsuite " `T.isPrefixOf` l -> do
            (cases, rest) <- casesOf ls
            ((file, name, cases) :) <$> suitesOf rest
      l : _ -> notReport ("unexpected line: " <> T.take 120 l)
      [] -> notReport "it ends before </testsuites>"
    casesOf = \case
      "  </testsuite>" : rest -> Right ([], rest)
      l : ls
        | "    <testcase " `T.isPrefixOf` l
        , Just name <- attribute "name" l
        , Just cls <- attribute "classname" l -> do
            let time = maybe 0 id (attribute "time" l >>= readMaybe . T.unpack)
                key = T.replace "." "/" cls <> "/" <> name
            (body, rest) <-
              if "/>" `T.isSuffixOf` l
                then Right ([], ls)
                else case break (== "    </testcase>") ls of
                  (b, end : rest') -> Right (b ++ [end], rest')
                  _ -> notReport ("the test case " <> key <> " is not closed")
            let kind = case body of
                  c : _
                    | "      <failure" `T.isPrefixOf` c -> KFailure
                    | "      <error" `T.isPrefixOf` c -> KError
                    | "      <skipped" `T.isPrefixOf` c -> KSkipped
                  _ -> KPass
            (more, rest'') <- casesOf rest
            pure (TestCase key (l : body) kind time : more, rest'')
      l : _ -> notReport ("unexpected line: " <> T.take 120 l)
      [] -> notReport "it ends inside a test suite"

-- | The value of an attribute in an element's line, as written (escaped).
attribute :: Text -> Text -> Maybe Text
attribute name l = case T.breakOn (" " <> name <> "=\"") l of
  (_, rest) | not (T.null rest) -> Just (T.takeWhile (/= '"') (T.drop (T.length name + 3) rest))
  _ -> Nothing
