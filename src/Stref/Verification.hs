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

-- | Several errors; the source is split into lines once, so that many
-- errors in a large file cost linear time.
renderErrors :: FilePath -> Text -> [VerificationError] -> Text
renderErrors file source = T.concat . map (renderWith (sourceLines source) file)

sourceLines :: Text -> Int -> Maybe Text
sourceLines source = let ls = Seq.fromList (T.lines source) in \l -> if l >= 1 then Seq.lookup (l - 1) ls else Nothing

renderWith :: (Int -> Maybe Text) -> FilePath -> VerificationError -> Text
renderWith lineAt file (VerificationError kind (Pos l c) msg) =
  T.unlines $
    [T.pack file <> ":" <> tshow l <> ":" <> tshow c <> ": error: " <> msg <> " [" <> kind <> "]"]
      ++ case lineAt l of
        Just srcLine ->
          let gutter = T.pack (show l) <> " | "
           in [ gutter <> srcLine
              , T.replicate (T.length gutter) " " <> T.map (\ch -> if ch == '\t' then '\t' else ' ') (T.take (c - 1) srcLine) <> "^"
              ]
        Nothing -> []
  where
    tshow :: Int -> Text
    tshow = T.pack . show
