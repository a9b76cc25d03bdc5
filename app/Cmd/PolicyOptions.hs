-- | The @--preset NAME@ and @--policy K=V@ options shared by the commands.
module Cmd.PolicyOptions
  ( policyAssignmentOption
  , presetOption
  , presetChoice
  , resolvePolicies
  ) where

import Data.Text (Text)
import qualified Data.Text as T
import Options.Applicative
import Stref.Policy

-- | @--policy K=V@, repeatable.
policyAssignmentOption :: Parser [(Text, Text)]
policyAssignmentOption =
  many
    ( option
        (eitherReader assignment)
        (long "policy" <> metavar "K=V" <> help "Set a policy, e.g. overflow=wrap (repeatable; see the policy table)")
    )
  where
    assignment s = case break (== '=') s of
      (k, '=' : v) | not (null k), not (null v) -> Right (T.pack k, T.pack v)
      _ -> Left ("expected K=V, e.g. overflow=wrap, not '" <> s <> "'")

presetOption :: Parser Text
presetOption =
  T.pack
    <$> strOption
      (long "preset" <> metavar "NAME" <> value "mastertool-xe" <> showDefault <> help ("Dialect preset the policies start from: " <> T.unpack (T.intercalate ", " (map fst presets))))

-- | @--preset NAME@ without a default: absent, each case or file uses its
-- own dialect's preset.
presetChoice :: Parser Text
presetChoice =
  T.pack
    <$> strOption
      (long "preset" <> metavar "NAME" <> help ("Run every case under this preset (" <> T.unpack (T.intercalate ", " (map fst presets)) <> "); by default each case runs under its dialect's preset"))

-- | The preset with the assignments applied in order.
resolvePolicies :: Text -> [(Text, Text)] -> Either Text Policies
resolvePolicies name assignments = do
  preset <- maybe (Left ("unknown preset '" <> name <> "'; the presets are: " <> T.intercalate ", " (map fst presets))) Right (lookupPreset name)
  foldl (\acc (k, v) -> acc >>= setPolicy k v) (Right preset) assignments
