-- | The conformance corpus on the reference engine: every case of
-- conformance/ is one example, and each must pass (issue: the corpus passes
-- 100 % on the reference). Expectations were computed by hand from the
-- manual; a failure here is a disagreement between the interpreter and the
-- manual's rules as the case states them.
module CorpusSpec (spec) where

import qualified Data.Set as S
import qualified Data.Text as T
import Conformance.Paths (engineScript, strefBinary)
import Stref.Conformance.Corpus
import Stref.Conformance.Runner
import Test.Hspec

spec :: Spec
spec = do
  corpus <- runIO (loadCorpus ["conformance"])
  describe "the conformance corpus on the reference engine" $ do
    it "loads without problems outside the cases" $
      corpusErrors corpus `shouldBe` []
    it "has at least 400 cases" $
      length (corpusEntries corpus) `shouldSatisfy` (>= 400)
    it "splits into three disjoint shards whose union is the whole, run in parallel through real processes" $ do
      let opts i = defaultRunOptions {roEngine = External (engineScript "unsupported"), roJobs = 4, roTimeout = 60, roShard = Just (i, 3)}
      shards <- mapM (\i -> runCorpus (opts i) corpus) [1, 2, 3]
      let ids = map (S.fromList . map resId) shards
          isUnsupported r = case resOutcome r of
            Unsupported _ -> True
            _ -> False
      sum (map S.size ids) `shouldBe` length (corpusEntries corpus)
      S.unions ids `shouldBe` S.fromList (map entryId (corpusEntries corpus))
      all (all isUnsupported) shards `shouldBe` True
    it "passes the tecomat corpus through `stref engine`, one process per case (corpus-format 4.4)" $ do
      bin <- strefBinary
      tc <- loadCorpus ["conformance/tecomat"]
      results <- runCorpus defaultRunOptions {roEngine = External (bin ++ " engine"), roJobs = 2, roTimeout = 120} tc
      length results `shouldSatisfy` (>= 100)
      [(resId r, resOutcome r) | r <- results, resOutcome r /= Pass] `shouldBe` []
    mapM_ caseExample (corpusEntries corpus)
  where
    caseExample entry = it (T.unpack (entryId entry)) $ case entry of
      Invalid _ _ msg -> expectationFailure (T.unpack msg)
      Loaded c -> do
        -- the step budget (2030) bounds every run; the timeout is only a
        -- safety net, generous so that an unoptimised build passes too
        outcome <- runOne defaultRunOptions {roTimeout = 300} c
        outcome `shouldBe` Pass
