-- | The parser (catalogue §§ 1, 5-8). STUB: owned by the parser work.
module Stref.Syntax.Parser
  ( parseModule
  ) where

import Data.Text (Text)
import Stref.Policy (Policies)
import Stref.Syntax
import Stref.Verification

-- | Parse a whole module. The policies matter for the lexical choices
-- (nested comments, ELSIF/ELSEIF). Errors carry the kinds of MT-VERR-1..6.
parseModule :: Policies -> FilePath -> Text -> Either VerificationError (Module Pos)
parseModule _ _ _ = Left (verificationError "not-implemented" (Pos 1 1) "the parser is not written yet")
