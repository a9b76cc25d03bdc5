-- | Verification-time errors (catalogue §10, Table 5-1): what the parser and
-- the checker report. Every error has a stable kebab-case kind (listed in
-- docs/diagnostics.md), a position and a message in the project's words.
module Stref.Verification
  ( VerificationError (..)
  , verificationError
  , renderError
  , renderErrors
  ) where

import Data.Text (Text)
import qualified Data.Sequence as Seq
import qualified Data.Text as T
import Stref.Syntax (Pos (..))

data VerificationError = VerificationError
  { veKind :: Text -- ^ stable name, e.g. @undeclared-variable@
  , vePos :: Pos
  , veMessage :: Text
  }
  deriving (Eq, Show)

verificationError :: Text -> Pos -> Text -> VerificationError
verificationError = VerificationError

-- | @file:line:col: error: message [kind]@, then the source line and a caret
-- under the column.
renderError :: FilePath -> Text -> VerificationError -> Text
renderError file source = renderWith (sourceLines source) file

-- | Several errors; the source is split into lines (and long lines into
-- chunks) once, so that many errors in a large file, or on one huge line,
-- cost linear time.
renderErrors :: FilePath -> Text -> [VerificationError] -> Text
renderErrors file source = T.concat . map (renderWith (sourceLines source) file)

-- | A source line as chunks of 'chunkSize' characters, with its length.
data SourceLine = SourceLine !Int (Seq.Seq Text)

chunkSize :: Int
chunkSize = 64

sourceLines :: Text -> Int -> Maybe SourceLine
sourceLines source =
  let ls = Seq.fromList [SourceLine (T.length t) (Seq.fromList (T.chunksOf chunkSize t)) | t <- T.lines source]
   in \l -> if l >= 1 then Seq.lookup (l - 1) ls else Nothing

-- | The characters @[from, from + len)@ of a line.
slice :: SourceLine -> Int -> Int -> Text
slice (SourceLine _ chunks) from len
  | len <= 0 = ""
  | otherwise =
      let first = from `div` chunkSize
          lastChunk = (from + len - 1) `div` chunkSize
          text = T.concat [c | i <- [first .. lastChunk], Just c <- [Seq.lookup i chunks]]
       in T.take len (T.drop (from - first * chunkSize) text)

renderWith :: (Int -> Maybe SourceLine) -> FilePath -> VerificationError -> Text
renderWith lineAt file (VerificationError kind (Pos l c) msg) =
  T.unlines $
    [T.pack file <> ":" <> tshow l <> ":" <> tshow c <> ": error: " <> msg <> " [" <> kind <> "]"]
      ++ case lineAt l of
        Just line ->
          let gutter = T.pack (show l) <> " | "
              (srcLine, col) = clipLine line c
           in [ gutter <> srcLine
              , T.replicate (T.length gutter) " " <> T.map (\ch -> if ch == '\t' then '\t' else ' ') (T.take (col - 1) srcLine) <> "^"
              ]
        Nothing -> []
  where
    tshow :: Int -> Text
    tshow = T.pack . show

-- | A long source line is shown as a window around the column (with "..."
-- where it is cut), so that many errors on one huge line do not print it
-- again and again in full.
clipLine :: SourceLine -> Int -> (Text, Int)
clipLine line@(SourceLine n _) col
  | n <= 2 * context = (slice line 0 n, col)
  | otherwise =
      let start = max 0 (col - 1 - context)
          before = if start > 0 then "..." else ""
          after = if start + 2 * context < n then "..." else ""
       in (before <> slice line start (2 * context) <> after, col - start + T.length before)
  where
    context = 80
