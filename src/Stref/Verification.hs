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
renderError file source (VerificationError kind (Pos l c) msg) =
  T.unlines $
    [T.pack file <> ":" <> tshow l <> ":" <> tshow c <> ": error: " <> msg <> " [" <> kind <> "]"]
      ++ case drop (l - 1) (T.lines source) of
        (srcLine : _) | l >= 1 ->
          let gutter = T.pack (show l) <> " | "
           in [ gutter <> srcLine
              , T.replicate (T.length gutter) " " <> T.map (\ch -> if ch == '\t' then '\t' else ' ') (T.take (c - 1) srcLine) <> "^"
              ]
        _ -> []
  where
    tshow :: Int -> Text
    tshow = T.pack . show

renderErrors :: FilePath -> Text -> [VerificationError] -> Text
renderErrors file source = T.concat . map (renderError file source)
