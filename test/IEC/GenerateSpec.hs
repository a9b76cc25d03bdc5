-- | Generated IEC programs (Stref.Generate.Iec) through the IEC core: the
-- generator produces only programs the checker accepts, every run ends in
-- values or a runtime error of a known kind, and laws that follow from the
-- rules hold on every program.
module IEC.GenerateSpec (spec) where

import Data.List (isInfixOf)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Conformance.Case (Case (..))
import Stref.Conformance.Corpus (Corpus (..), Entry (..), loadCorpus)
import Stref.Conformance.Protocol (Scalar)
import Stref.IEC.Check (ProgramChoice (..))
import Stref.IEC.Engine
import Stref.IEC.Eval (Stop (..), readVariablePath)
import Stref.IEC.Values (Fault (..))
import Stref.Generate.Iec
import Stref.Policy
import Stref.Verification (VerificationError (..))
import Test.Hspec
import Test.QuickCheck
import Test.QuickCheck.Gen (unGen)
import Test.QuickCheck.Random (mkQCGen)

-- | What the example engine lacks (conformance/engines/example/lacking-features.txt).
partial :: [Text]
partial = ["sint", "usint", "uint", "bit-strings", "real", "time", "case", "for", "standard-fb", "functions", "conversions", "division", "literal-expressions"]

-- | The observable outcome of a program: every variable and the error kind.
data Outcome = Rejected Text | Failed Text | Ran (M.Map Text Scalar) (Maybe Text)
  deriving (Eq, Show)

outcome :: Policies -> GenProgram -> Outcome
outcome pol gp = case runProgram pol "gen.st" (renderProgram gp) ProgramsOfConfiguration 10 [] (replicate (gpCalls gp) (Scan [])) of
  Left e -> Rejected (veKind e <> ": " <> veMessage e)
  Right (Left e) -> Failed e
  Right (Right r) ->
    let vars = M.fromList [(p, programScalar (rrProgram r) v) | p <- observedPaths (gpSupport gp), Right steps <- [parseVarPath p], Just (v, _) <- [readVariablePath (rrProgram r) (rrMachine r) steps]]
     in Ran vars ((\(_, StopFault _ f) -> faultKind f) <$> rrError r)

knownKinds :: [Text]
knownKinds = ["division-by-zero", "index-out-of-range", "subrange", "overflow", "conversion", "watchdog", "call-depth"]

prop :: Testable p => (GenProgram -> p) -> Property
prop = forAllShrink (genProgram fullSupport) shrinkProgram

-- | Every expression of a program.
expressions :: GenProgram -> [GExpr]
expressions = concatMap stmt . gpBody
  where
    stmt = \case
      GAssign _ e -> expr e
      GIf c a b -> expr c ++ concatMap stmt (a ++ b)
      GCase _ arms els -> concatMap stmt (concatMap snd arms ++ els)
      GFor _ _ _ b -> concatMap stmt b
      GTimer i p -> expr i ++ expr p
      GCounter c -> expr c
      GPointAt _ -> []
      GStore e -> expr e
    expr e = e : case e of
      GBin _ _ a b -> expr a ++ expr b
      GUn _ _ a -> expr a
      GConv _ _ a -> expr a
      GCall _ _ as -> concatMap expr as
      _ -> []

-- | An operation none of whose leaves is a variable or an FB output.
literalOperation :: GExpr -> Bool
literalOperation = \case
  GLit {} -> False
  GVar {} -> False
  GTimerQ -> False
  GCounterCV _ -> False
  e -> all isLiteral (leaves e)
  where
    isLiteral = \case
      GLit {} -> True
      _ -> False
    leaves = \case
      GBin _ _ a b -> leaves a ++ leaves b
      GUn _ _ a -> leaves a
      GConv _ _ a -> leaves a
      GCall _ _ as -> concatMap leaves as
      x -> [x]

spec :: Spec
spec = describe "IEC.Generate: generated tecomat programs" $ do
  it "are accepted by the checker and run to values or a runtime error of a known kind" $
    withMaxSuccess 200 . prop $ \gp -> case outcome tecomat gp of
      Ran vars err -> counterexample (T.unpack (renderProgram gp)) (M.size vars == length (observedPaths (gpSupport gp)) && maybe True (`elem` knownKinds) err)
      o -> counterexample (T.unpack (renderProgram gp) ++ "\n" ++ show o) False
  it "leave out what an engine lacks (explore --features-file): no excluded type, statement, FB or function, no operation of literals only, and still accepted" $
    withMaxSuccess 200 . forAll (genProgram (withoutFeatures partial fullSupport)) $ \gp ->
      let src = T.unpack (renderProgram gp)
          banned = ["REAL", "TIME", "SINT", "UINT", "BYTE", "WORD", "FOR ", "CASE ", "TON", "CTU", "_TO_", "MAX(", "MIN(", "LIMIT(", "ABS(", "SHL(", " / ", " MOD "]
       in counterexample src $
            conjoin [counterexample ("uses " ++ b) (not (b `isInfixOf` src)) | b <- banned]
              .&&. counterexample "an operation of literals only" (not (any literalOperation (expressions gp)))
              .&&. case outcome tecomat gp of
                Ran vars _ -> M.keys vars === ["MAIN.b1", "MAIN.b2", "MAIN.di1", "MAIN.di2", "MAIN.i1", "MAIN.i2"]
                o -> counterexample (show o) False
  it "know only feature names that corpus cases carry (the vocabulary of --features-file)" $ do
    corpus <- loadCorpus ["conformance"]
    let tags = [f | Loaded c <- corpusEntries corpus, f <- caseFeatures c]
    [f | f <- knownFeatures, f `notElem` tags] `shouldBe` []
  it "under nexto (codesysSupport) are accepted by its checker and run to values or a runtime error of a known kind" $
    withMaxSuccess 200 . forAll (genProgram codesysSupport) $ \gp -> case outcome nexto gp of
      Ran vars err -> counterexample (T.unpack (renderProgram gp)) (M.size vars == length (observedPaths (gpSupport gp)) && maybe True (`elem` knownKinds) err)
      o -> counterexample (T.unpack (renderProgram gp) ++ "\n" ++ show o) False
  it "under nexto use the 64-bit types, the pointer, the method and CODESYS's spelling of CTU" $ do
    let srcs = concat [T.unpack (renderProgram (unGen (genProgram codesysSupport) (mkQCGen sd) 30)) | sd <- [1 .. 60 :: Int]]
    [b | b <- ["LINT", "ULINT", "LWORD", "pi1^", "ADR(", "acc.Add(x :=", "RESET := FALSE"], not (b `isInfixOf` srcs)] `shouldBe` []
  it "use every part of the language when nothing is left out" $
    let srcs = concat [T.unpack (renderProgram (generatedWith s)) | s <- [1 .. 60 :: Int]]
        generatedWith s = unGen (genProgram fullSupport) (mkQCGen s) 30
     in do
          [b | b <- ["REAL", "LREAL", "TIME", "BYTE", "WORD", "FOR ", "CASE ", "IF ", "t(IN", "c(CU", "_TO_", "MAX(", "LIMIT(", "ABS(", "SHL(", " / ", " MOD "], not (b `isInfixOf` srcs)] `shouldBe` []
          -- and nothing of CODESYS's under tecomat
          [b | b <- ["LINT", "LWORD", "POINTER", "METHOD", "RESET :="], b `isInfixOf` srcs] `shouldBe` []
  it "give the same results whether FOR evaluates its (constant) bounds once or at every test (TC-STMT-26)" $
    withMaxSuccess 100 . prop $ \gp ->
      outcome tecomat {pForBounds = ForOnce} gp === outcome tecomat {pForBounds = ForEveryIteration} gp
  it "give the same results under short-circuit and eager AND/OR when eager evaluation raises no error (TC-OP-6)" $
    withMaxSuccess 200 . prop $ \gp -> case outcome tecomat {pShortCircuit = Eager} gp of
      r@(Ran _ Nothing) -> r === outcome tecomat {pShortCircuit = ShortCircuit} gp
      _ -> property True
  it "give the same results under after-error stop and continue when no cycle fails" $
    withMaxSuccess 200 . prop $ \gp -> case outcome tecomat gp of
      r@(Ran _ Nothing) -> r === outcome tecomat {pAfterError = ContinueNextCycle} gp
      _ -> property True
  it "give the same results under every overflow alternative when saturate and wrap agree and trap raises nothing" $
    withMaxSuccess 200 . prop $ \gp -> case outcome tecomat {pOverflow = Trap} gp of
      r@(Ran _ Nothing) -> r === outcome tecomat {pOverflow = Wrap} gp .&&. r === outcome tecomat {pOverflow = Saturate} gp
      _ -> property True
