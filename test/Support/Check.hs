-- | Helpers for the checker's specs: check ST text, list error kinds, and
-- wrap fragments into a PROGRAM.
module Support.Check
  ( checkText
  , checkTextWith
  , kindsOf
  , kindsWith
  , program
  , programF
  , rejects
  , accepts
  , acceptsWith
  , rejectsWith
  , elaborate
  , elaborateWith
  ) where

import Data.Text (Text)
import qualified Data.Text as T
import Stref.Check (checkModule)
import Stref.Checked
import Stref.Policy
import Stref.Syntax.Parser (parseModule)
import Stref.Verification
import Test.Hspec

checkTextWith :: Policies -> ModuleKind -> Text -> Either [VerificationError] CModule
checkTextWith p k src = case parseModule p "test.st" src of
  Left e -> Left [e {veKind = "PARSE:" <> veKind e}]
  Right m -> checkModule p k m

checkText :: Text -> Either [VerificationError] CModule
checkText = checkTextWith mastertoolXE FunctionModule

kindsWith :: Policies -> ModuleKind -> Text -> [Text]
kindsWith p k = either (map veKind) (const []) . checkTextWith p k

-- | The error kinds of a module checked as an F module under MasterTool XE.
kindsOf :: Text -> [Text]
kindsOf = kindsWith mastertoolXE FunctionModule

-- | @PROGRAM P VAR <vars> END_VAR <body> END_PROGRAM@ after some globals.
program :: Text -> Text -> Text
program vars body = "PROGRAM P\nVAR\n" <> vars <> "\nEND_VAR\n" <> body <> "\nEND_PROGRAM\n"

-- | A module with globals/functions first, then the program.
programF :: Text -> Text -> Text -> Text
programF before vars body = before <> "\n" <> program vars body

rejects :: Text -> Text -> Expectation
rejects kind src = case checkText src of
  Left es -> map veKind es `shouldContain` [kind]
  Right _ -> expectationFailure ("accepted, but expected " <> T.unpack kind <> ":\n" <> T.unpack src)

rejectsWith :: Policies -> ModuleKind -> Text -> Text -> Expectation
rejectsWith p k kind src = case checkTextWith p k src of
  Left es -> map veKind es `shouldContain` [kind]
  Right _ -> expectationFailure ("accepted, but expected " <> T.unpack kind <> ":\n" <> T.unpack src)

accepts :: Text -> Expectation
accepts = acceptsWith mastertoolXE FunctionModule

acceptsWith :: Policies -> ModuleKind -> Text -> Expectation
acceptsWith p k src = case checkTextWith p k src of
  Left es -> expectationFailure ("rejected: " <> show [(veKind e, veMessage e) | e <- es] <> "\n" <> T.unpack src)
  Right _ -> pure ()

elaborateWith :: Policies -> Text -> IO CModule
elaborateWith p src = case checkTextWith p FunctionModule src of
  Left es -> expectationFailure ("rejected: " <> show [(veKind e, veMessage e) | e <- es]) >> fail "rejected"
  Right m -> pure m

elaborate :: Text -> IO CModule
elaborate = elaborateWith mastertoolXE
