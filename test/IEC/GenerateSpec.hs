-- | Generated IEC programs (Stref.Generate.Iec) through the IEC core: the
-- generator produces only programs the checker accepts, every run ends in
-- values or a runtime error of a known kind, and laws that follow from the
-- rules hold on every program.
module IEC.GenerateSpec (spec) where

import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
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

-- | The observable outcome of a program: every variable and the error kind.
data Outcome = Rejected Text | Failed Text | Ran (M.Map Text Scalar) (Maybe Text)
  deriving (Eq, Show)

outcome :: Policies -> GenProgram -> Outcome
outcome pol gp = case runProgram pol "gen.st" (renderProgram gp) ProgramsOfConfiguration 10 [] (replicate (gpCalls gp) (Scan [])) of
  Left e -> Rejected (veKind e <> ": " <> veMessage e)
  Right (Left e) -> Failed e
  Right (Right r) ->
    let vars = M.fromList [(p, valueScalar v) | p <- observedPaths, Right steps <- [parseVarPath p], Just (v, _) <- [readVariablePath (rrProgram r) (rrMachine r) steps]]
     in Ran vars ((\(_, StopFault _ f) -> faultKind f) <$> rrError r)

knownKinds :: [Text]
knownKinds = ["division-by-zero", "index-out-of-range", "subrange", "overflow", "conversion", "watchdog", "call-depth"]

prop :: Testable p => (GenProgram -> p) -> Property
prop = forAllShrink genProgram shrinkProgram

spec :: Spec
spec = describe "IEC.Generate: generated tecomat programs" $ do
  it "are accepted by the checker and run to values or a runtime error of a known kind" $
    withMaxSuccess 200 . prop $ \gp -> case outcome tecomat gp of
      Ran vars err -> counterexample (T.unpack (renderProgram gp)) (M.size vars == length observedPaths && maybe True (`elem` knownKinds) err)
      o -> counterexample (T.unpack (renderProgram gp) ++ "\n" ++ show o) False
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
