module ConformanceCoverageSpec (spec) where

import Conformance.Paths
import Stref.Conformance.Corpus
import Stref.Conformance.Coverage
import Stref.Conformance.Rules
import System.Exit (ExitCode (..))
import System.Process (readProcessWithExitCode)
import Test.Hspec

spec :: Spec
spec = describe "Conformance coverage" $ do
  it "lists the cases citing each rule, in the order of RULES" $ do
    corpus <- loadCorpus [fixtureCorpus]
    let rcs = coverage (corpusRules corpus) [c | Loaded c <- corpusEntries corpus]
    [(ruleId (rcRule rc), rcCases rc) | rc <- rcs]
      `shouldBe` [ ("MT-OP-6", ["mastertool-xe/arith/int-add-saturates", "mastertool-xe/arith/real-rounding", "mastertool-xe/arith/real-sum"])
                 , ("MT-OP-7", ["mastertool-xe/arith/int-add-saturates"])
                 , ("MT-EXEC-9", ["mastertool-xe/calls/div-zero", "mastertool-xe/calls/named-vars", "mastertool-xe/calls/three-calls"])
                 , ("MT-LEX-1", [])
                 , ("MT-OP-99", [])
                 ]
    -- MT-LEX-1 is untestable: only MT-OP-99 is missing, 3 of 4 testable covered
    map (ruleId . rcRule) (uncoveredTestable rcs) `shouldBe` ["MT-OP-99"]
    coveredFraction rcs `shouldBe` (3, 4)

  it "`stref coverage` prints the share and fails only with --strict" $ do
    stref <- strefBinary
    (code, out, _) <- readProcessWithExitCode stref ["coverage", fixtureCorpus] ""
    code `shouldBe` ExitSuccess
    last (lines out) `shouldBe` "coverage: 3/4 testable rules (75.0%)"
    (code', _, _) <- readProcessWithExitCode stref ["coverage", "--strict", fixtureCorpus] ""
    code' `shouldBe` ExitFailure 1
