-- | The verifier (catalogue §§ 2-10): static semantics of MasterTool XE.
-- STUB: owned by the checker work.
module Stref.Check
  ( checkModule
  ) where

import Stref.Checked
import Stref.Policy (Policies)
import Stref.Syntax
import Stref.Verification

-- | Check a parsed module as a P or F module; all errors the checker can find.
checkModule :: Policies -> ModuleKind -> Module Pos -> Either [VerificationError] CModule
checkModule _ _ _ = Left [verificationError "not-implemented" (Pos 1 1) "the checker is not written yet"]
