-- | Finding and loading the cases of a corpus. A dialect's directory is the
-- nearest directory above a case that holds a RULES index; its name is the
-- dialect, and a case's id is the dialect followed by the case's path below
-- it without @.st@ (@mastertool-xe/arith/int-add-saturates@). The area is
-- the first directory below the dialect's.
module Stref.Conformance.Corpus
  ( Entry (..)
  , entryId
  , Corpus (..)
  , loadCorpus
  , loadCorpusWith
  , findCaseFiles
  , readKnownFailures
  , readListFile
  , ruleTitles
  , areaOfId
  ) where

import Control.Exception (IOException, evaluate, try)
import Control.Monad (forM)
import Data.Containers.ListUtils (nubOrd)
import Data.List (isSuffixOf, sort, sortOn)
import qualified Data.Map.Strict as M
import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.ByteString as BS
import System.Directory
import System.FilePath
import Stref.Source (decodeSource, renderEncodingError)
import Stref.Conformance.Case
import Stref.Conformance.Parallel (inParallel)
import Stref.Conformance.Rules

-- | A case file: loaded, or the precise reason it could not be.
data Entry
  = Loaded Case
  | Invalid Text FilePath Text -- ^ id (as far as known), file, @file:line: message@
  deriving (Eq, Show)

entryId :: Entry -> Text
entryId = \case
  Loaded c -> caseId c
  Invalid i _ _ -> i

data Corpus = Corpus
  { corpusEntries :: [Entry] -- ^ sorted by id
  , corpusRules :: M.Map Text [Rule] -- ^ dialect → its RULES index
  , corpusErrors :: [Text] -- ^ problems outside any case (a bad RULES file, a missing path)
  }

-- | The area of a case, @<dialect>/<area>@, read from its id as the loader
-- makes ids: for a case that did not load, whose area is not otherwise
-- known. A case directly in its dialect's directory has the empty area.
areaOfId :: Text -> Text
areaOfId i = case T.splitOn "/" i of
  dialect : area : _ : _ -> dialect <> "/" <> area
  dialect : _ -> dialect <> "/"
  [] -> i

-- | Every rule id of the corpus's indexes with its title.
ruleTitles :: Corpus -> M.Map Text Text
ruleTitles corpus = M.fromList [(ruleId r, ruleTitle r) | rs <- M.elems (corpusRules corpus), r <- rs]

-- | Every @.st@ file under the given paths (a file is taken as it is).
findCaseFiles :: [FilePath] -> IO ([Text], [FilePath])
findCaseFiles paths = do
  found <- forM paths $ \p -> do
    isFile <- doesFileExist p
    isDir <- doesDirectoryExist p
    if isFile
      then pure ([], [p])
      else
        if isDir
          then ([],) <$> walk p
          else pure (["no such file or directory: " <> T.pack p], [])
  pure (concatMap fst found, nubOrd (concatMap snd found))
  where
    walk dir = do
      names <- sort <$> listDirectory dir
      fmap concat . forM names $ \n -> do
        let p = dir </> n
        isDir <- doesDirectoryExist p
        if isDir
          then walk p
          else pure [p | ".st" `isSuffixOf` n]

-- | Load every case under the paths, each against its dialect's RULES.
loadCorpus :: [FilePath] -> IO Corpus
loadCorpus = loadCorpusWith 1

-- | 'loadCorpus' with the cases read and parsed by @jobs@ workers.
loadCorpusWith :: Int -> [FilePath] -> IO Corpus
loadCorpusWith jobs paths = do
  (missing, files) <- findCaseFiles paths
  located <- forM files $ \f -> do
    abs' <- makeAbsolute f
    dir <- findDialectDir (takeDirectory abs')
    pure (f, abs', dir)
  let dialectDirs = S.toList (S.fromList [d | (_, _, Just d) <- located])
  indexes <- forM dialectDirs $ \d -> do
    let rf = d </> rulesFileName
    txt <- readUtf8 rf
    pure (d, either (Left . pure) (parseRules rf) txt)
  -- each dialect's rule ids, as a set built once
  let indexOf = M.fromList [(d, fmap (\rules -> S.fromList (map ruleId rules)) r) | (d, r) <- indexes]
      rulesErrors = concat [es | (_, Left es) <- indexes]
  let eachCase work
        | jobs <= 1 = forM located work
        | otherwise = inParallel jobs (\x -> work x >>= evaluate) located -- parsed by the worker
  entries <- eachCase $ \(f, abs', mdir) -> case mdir of
    Nothing ->
      pure (Invalid (T.pack (dropExtension f)) f (T.pack f <> ":1: no RULES index in any directory above this case; a corpus is laid out as <dialect>/RULES and <dialect>/<area>/<case>.st"))
    Just d -> do
      let dialect = T.pack (takeFileName d)
          rel = makeRelative d abs'
          parts = splitDirectories (dropExtension rel)
          cid = T.intercalate "/" (dialect : map T.pack parts)
          area = case parts of
            (a : _ : _) -> T.pack a
            _ -> ""
          origin = CaseOrigin cid dialect area
      case M.lookup d indexOf of
        Just (Right known) -> do
          txt <- readUtf8 f
          pure $ case txt of
            Left e -> Invalid cid f e
            Right src -> either (Invalid cid f) Loaded (parseCase f origin (`S.member` known) src)
        _ -> pure (Invalid cid f (T.pack f <> ":1: the dialect's RULES index is invalid (see above)"))
  pure
    Corpus
      { corpusEntries = sortOn entryId entries
      , corpusRules = M.fromList [(T.pack (takeFileName d), rs) | (d, Right rs) <- indexes]
      , corpusErrors = missing ++ rulesErrors
      }
  where
    findDialectDir dir = do
      has <- doesFileExist (dir </> rulesFileName)
      if has
        then pure (Just dir)
        else
          let up = takeDirectory dir
           in if up == dir then pure Nothing else findDialectDir up

readUtf8 :: FilePath -> IO (Either Text Text)
readUtf8 f = do
  r <- try (BS.readFile f) :: IO (Either IOException BS.ByteString)
  pure $ case r of
    Left e -> Left (T.pack f <> ":1: cannot read: " <> T.pack (show e))
    Right bs -> case decodeSource bs of
      Left bad -> Left (T.stripEnd (renderEncodingError f bad))
      Right t -> Right (T.replace "\r\n" "\n" t)

-- | A known-failures file: one case id per line; @#@ comments and blank
-- lines are ignored.
readKnownFailures :: FilePath -> IO (Either Text (S.Set Text))
readKnownFailures f = fmap S.fromList <$> readListFile "known-failures" f

-- | A file of names, one a line; @#@ starts a comment, blank lines are
-- ignored (the known failures, an engine's features file).
readListFile :: Text -> FilePath -> IO (Either Text [Text])
readListFile what f = do
  exists <- doesFileExist f
  if not exists
    then pure (Left (what <> " file not found: " <> T.pack f))
    else do
      r <- readUtf8 f
      pure $ fmap (filter (not . T.null) . map (T.strip . T.takeWhile (/= '#')) . T.lines) r

