-- | Which rules of a dialect's index the corpus checks: every rule with the
-- cases citing it.
module Stref.Conformance.Coverage
  ( RuleCoverage (..)
  , coverage
  , uncoveredTestable
  , coveredFraction
  ) where

import qualified Data.Map.Strict as M
import Data.Text (Text)
import Stref.Conformance.Case
import Stref.Conformance.Rules

data RuleCoverage = RuleCoverage
  { rcDialect :: Text
  , rcRule :: Rule
  , rcCases :: [Text] -- ^ ids of the cases citing the rule
  }
  deriving (Eq, Show)

-- | In the order of each index.
coverage :: M.Map Text [Rule] -> [Case] -> [RuleCoverage]
coverage indexes cases =
  [ RuleCoverage dialect r (M.findWithDefault [] (dialect, ruleId r) citing)
  | (dialect, rules) <- M.toList indexes
  , r <- rules
  ]
  where
    citing = M.fromListWith (flip (++)) [((caseDialect c, rid), [caseId c]) | c <- cases, rid <- caseRules c]

uncoveredTestable :: [RuleCoverage] -> [RuleCoverage]
uncoveredTestable = filter (\rc -> null (rcCases rc) && ruleUntestable (rcRule rc) == Nothing)

-- | Covered testable rules, testable rules.
coveredFraction :: [RuleCoverage] -> (Int, Int)
coveredFraction rcs =
  let testable = [rc | rc <- rcs, ruleUntestable (rcRule rc) == Nothing]
   in (length [() | rc <- testable, not (null (rcCases rc))], length testable)
