-- | The printer: normalised ST whose parse is the same tree. STUB: owned by
-- the parser work.
module Stref.Syntax.Pretty
  ( prettyModule
  ) where

import Data.Text (Text)
import Stref.Syntax

prettyModule :: Module a -> Text
prettyModule _ = ""
