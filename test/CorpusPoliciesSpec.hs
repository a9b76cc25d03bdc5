-- | The corpus is complete for every policy alternative: a case whose result
-- depends on an implementation-defined choice says so with an @expect-if@
-- entry for each alternative (conformance/README.md). Two checks:
--
-- * for every alternative, the in-process reference running it (and declaring
--   it) passes every case;
-- * an external engine that wraps on overflow, judged as if it saturated,
--   fails exactly the cases whose expectation under @overflow = wrap@ differs
--   from their MasterTool expectation, and no other.
--
-- The cases expected to end in the step budget's error 2030 are left out of
-- both sweeps: they run 10^7 steps each, far the slowest of the corpus, and
-- CorpusSpec runs them under the preset already.
module CorpusPoliciesSpec (spec) where

import Conformance.Paths (strefBinary)
import qualified Data.Set as S
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Conformance.Case
import Stref.Conformance.Corpus
import Stref.Conformance.Runner
import Stref.Policy (Policies, PolicyInfo (..), mastertoolXE, nexto, policyTable, setPolicy, tecomat)
import Test.Hspec

-- | Every alternative that differs from the MasterTool XE preset.
alternatives :: [(Text, Text)]
alternatives =
  [ ("overflow", "wrap")
  , ("overflow", "trap")
  , ("arith-width", "promote-32")
  , ("div-zero", "zero")
  , ("div-zero", "trap")
  , ("real-div-zero", "ieee")
  , ("real-overflow", "ieee")
  , ("mod-zero", "error")
  , ("mod-sign", "euclidean")
  , ("real-to-int", "round-even-saturate")
  , ("real-to-int", "round-even-wrap")
  , ("narrow-int", "saturate")
  , ("implicit-conversions", "iec-widening")
  , ("implicit-conversions", "codesys")
  , ("name-resolution", "local-wins")
  , ("for-bounds", "every-iteration")
  , ("for-at-type-max", "follow-overflow-policy")
  , ("short-circuit", "short-circuit")
  , ("lifetime", "retained")
  , ("index-out-of-range", "clamp")
  , ("index-out-of-range", "trap")
  , ("nested-comments", "yes")
  , ("elsif-keyword", "ELSIF")
  , ("error-line-before-start", "-1")
  , ("identifier-length", "unlimited")
  ]

-- | Policies that change what a program may say rather than what it means,
-- so that a case written for one alternative is not a program of the other:
-- lifetime=per-call is the MasterTool controller's (the IEC engine answers
-- it with unsupported, IEC.EngineSpec checks that); standard-library renames
-- the standard FBs' inputs (IEC.EngineSpec runs both libraries).
interfacePolicies :: [Text]
interfacePolicies = ["lifetime", "standard-library", "reserved-names"]

-- | The policies that give or take parts of CODESYS's language
-- (extensions, bit-string arithmetic, program calls, writing an FB's inputs
-- and outputs, TIME literals beyond the other's range) or change what an
-- enumerated value is: a case of one
-- dialect is not a program of the other, or an IEC rejection becomes a
-- CODESYS program, under the other alternative (IEC.NextoSpec runs both).
codesysInterface :: [Text]
codesysInterface = ["extensions", "enumerations", "bit-string-arithmetic", "program-calls", "fb-access", "time-range"]

policiesWith :: (Text, Text) -> Policies
policiesWith (k, v) = either (error . T.unpack) id (setPolicy k v mastertoolXE)

-- | Does the case, under these policies, expect the step budget's error?
stepBudgetCase :: Policies -> Case -> Bool
stepBudgetCase p c = case exError (effectiveExpect p c) of
  Just (ErrCode 2030 _ _) -> True
  _ -> False

-- | The loaded cases, without those that run into the step budget under
-- either policy record.
quickCases :: [Policies] -> Corpus -> Corpus
quickCases ps corpus = corpus {corpusEntries = filter keep (corpusEntries corpus)}
  where
    keep (Loaded c) = not (any (`stepBudgetCase` c) ps)
    keep (Invalid {}) = True

failures :: [CaseResult] -> [(Text, Outcome)]
failures rs = [(resId r, resOutcome r) | r <- rs, resOutcome r /= Pass]

-- | Every alternative of every enumerated policy that differs from the
-- preset's choice.
alternativesFrom :: Policies -> [(Text, Text)]
alternativesFrom p = [(piName i, a) | i <- policyTable, a <- piAlternatives i, a /= piGet i p]

spec :: Spec
spec = do
  corpus <- runIO (loadCorpus ["conformance/mastertool-xe"])
  tecomatCorpus <- runIO (loadCorpus ["conformance/tecomat"])
  nextoCorpus <- runIO (loadCorpus ["conformance/nexto"])
  describe "the corpus under every policy alternative (reference, declared = run)" $
    mapM_ (sweep corpus) alternatives
  describe "the tecomat corpus under every policy alternative (the preset with one choice changed)" $
    mapM_ (sweepDialect tecomatCorpus) (filter ((`notElem` (interfacePolicies ++ codesysInterface)) . fst) (alternativesFrom tecomat) ++ [("identifier-length", "unlimited")])
  describe "the nexto corpus under every policy alternative (the preset with one choice changed)" $
    mapM_ (sweepDialect nextoCorpus) (filter ((`notElem` (interfacePolicies ++ codesysInterface)) . fst) (alternativesFrom nexto))
  describe "an engine that wraps on overflow, judged under the preset" $
    it "fails exactly the cases whose overflow=wrap expectation differs from expect" $ do
      bin <- strefBinary
      let wrap = policiesWith ("overflow", "wrap")
          quick = quickCases [mastertoolXE, wrap] corpus
          differs c = effectiveExpect wrap c /= effectiveExpect mastertoolXE c
          expected = S.fromList [caseId c | Loaded c <- corpusEntries quick, differs c]
          opts = defaultRunOptions {roEngine = External (bin ++ " engine --policy overflow=wrap"), roJobs = 2, roTimeout = 60}
      results <- runCorpus opts quick
      S.size expected `shouldSatisfy` (>= 10)
      [(i, o) | (i, o) <- failures results, not (isFail o)] `shouldBe` []
      S.fromList (map fst (failures results)) `shouldBe` expected
  where
    isFail = \case
      Fail _ -> True
      _ -> False
    sweepDialect corpus alt@(k, v) = it (T.unpack (k <> "=" <> v)) $ do
      let opts = defaultRunOptions {roOverrides = Just [alt], roJobs = 2, roTimeout = 120}
      results <- runCorpus opts corpus
      length results `shouldSatisfy` (>= 100)
      failures results `shouldBe` []
    sweep corpus alt@(k, v) = it (T.unpack (k <> "=" <> v)) $ do
      let p = policiesWith alt
          opts = defaultRunOptions {roEngine = Reference [alt], roPolicies = p, roOverrides = Nothing, roJobs = 2, roTimeout = 60}
      results <- runCorpus opts (quickCases [p] corpus)
      failures results `shouldBe` []
