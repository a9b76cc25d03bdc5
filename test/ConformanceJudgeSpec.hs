module ConformanceJudgeSpec (spec) where

import Data.List.NonEmpty (NonEmpty (..))
import qualified Data.Map.Strict as M
import Stref.Conformance.Case
import Stref.Conformance.Protocol
import Stref.Conformance.Runner
import Stref.Operands
import Test.Hspec
import qualified Data.Text as T

m12, f1 :: Operand
m12 = OpSimple KM 12
f1 = OpSimple KF 1

expecting :: [(Operand, ExpValue)] -> Expect
expecting ops = emptyExpect {exOperands = M.fromList ops}

answered :: [(Text', Scalar)] -> Answer
answered ops = AnswerRun VerdictOk emptyObservation {obOperands = M.fromList ops}

type Text' = T.Text

spec :: Spec
spec = describe "Conformance judging" $ do
  describe "integer operands are bit patterns of their width" $ do
    it "-1 expected, 65535 answered: the same 16#FFFF" $
      judge (expecting [(m12, EInt (-1))]) (answered [("%M0012", SNumber 65535)]) `shouldBe` Pass
    it "65535 expected, -1 answered: the same 16#FFFF" $
      judge (expecting [(m12, EInt 65535)]) (answered [("%M12", SNumber (-1))]) `shouldBe` Pass
    it "a different pattern fails with the operand, expected and actual value" $
      judge (expecting [(m12, EInt (-1))]) (answered [("%M0012", SNumber 65534)])
        `shouldBe` Fail (Difference "%M0012" "-1" "65534" :| [])
    it "an operand the engine did not report fails" $
      judge (expecting [(m12, EInt 7)]) (answered []) `shouldBe` Fail (Difference "%M0012" "7" "not reported" :| [])
    it "a %M answer out of 16-bit range does not match its low bits" $
      -- 65536 + 7 is no reading of a 16-bit pattern
      judge (expecting [(m12, EInt 7)]) (answered [("%M0012", SNumber 65543)]) `shouldSatisfy` isFail

  describe "REAL operands compare binary32 values" $ do
    it "0.1 expected, 0.1 answered" $
      judge (expecting [(f1, EReal 0.1)]) (answered [("%F0001", SNumber 0.1)]) `shouldBe` Pass
    it "0.1 expected, its bits 0x3DCCCCCD answered" $
      judge (expecting [(f1, EReal 0.1)]) (answered [("%F0001", SBits 0x3DCCCCCD)]) `shouldBe` Pass
    it "the next binary32 up (0x3DCCCCCE) differs" $
      judge (expecting [(f1, EReal 0.1)]) (answered [("%F0001", SBits 0x3DCCCCCE)]) `shouldSatisfy` isFail
    it "any NaN matches nan" $
      judge (expecting [(f1, ENaN)]) (answered [("%F0001", SBits 0xFFC00001)]) `shouldBe` Pass
    it "-0.0 is not 0.0" $
      judge (expecting [(f1, EReal 0)]) (answered [("%F0001", SBits 0x80000000)]) `shouldSatisfy` isFail

  describe "verdicts and errors" $ do
    it "unsupported is its own result" $
      judge emptyExpect (AnswerUnsupported "REAL") `shouldBe` Unsupported "REAL"
    it "a rejection where a run was expected fails on the verdict" $
      judge emptyExpect (AnswerRejected (Just 5) Nothing "Variable X was not declared.")
        `shouldBe` Fail (Difference "verdict" "ok" "rejected at line 5: Variable X was not declared." :| [])
    it "a rejection compares line and kind when the case states them" $ do
      let ex = emptyExpect {exReject = Just (ExpReject (Just 5) (Just "undeclared-variable"))}
      judge ex (AnswerRejected (Just 5) (Just "undeclared-variable") "m") `shouldBe` Pass
      judge ex (AnswerRejected (Just 6) (Just "undeclared-variable") "m") `shouldBe` Fail (Difference "reject.line" "5" "6 (m)" :| [])
      -- an engine that does not know the project's kinds is not judged on them
      judge ex (AnswerRejected (Just 5) Nothing "m") `shouldBe` Pass
    it "a runtime error compares code, line and complements" $ do
      let ex = emptyExpect {exError = Just (ErrCode 2020 (Just 10) Nothing)}
          err l = AnswerRun VerdictRuntimeError emptyObservation {obError = Just (ErrorReport (Just 2020) Nothing (Just l) (Just (0, 0, 0)))}
      judge ex (err 10) `shouldBe` Pass
      judge ex (err 11) `shouldBe` Fail (Difference "error.line" "10" "11" :| [])
    it "error: none fails when the engine reports an error" $
      judge emptyExpect {exError = Just ErrNone} (AnswerRun VerdictOk emptyObservation {obError = Just (ErrorReport (Just 2015) Nothing (Just 3) Nothing)})
        `shouldBe` Fail (Difference "error" "none" "error 2015 at line 3" :| [])
    it "outputs are compared by name" $
      judge emptyExpect {exOutputs = M.fromList [(2, True)]} (AnswerRun VerdictOk emptyObservation {obOutputs = M.fromList [("OUTPUT2", False)]})
        `shouldBe` Fail (Difference "OUTPUT2" "true" "false" :| [])
    it "every difference is listed, not only the first: verdict, error, operands, variables, outputs" $ do
      let ex =
            emptyExpect
              { exOperands = M.fromList [(m12, EInt 7), (OpSimple KM 13, EInt 1), (OpSimple KM 14, EInt 3)]
              , exVars = M.fromList [("P.X", EInt 5)]
              , exOutputs = M.fromList [(2, True)]
              , exError = Just ErrNone
              }
          answer =
            AnswerRun VerdictRuntimeError emptyObservation
              { obOperands = M.fromList [("%M0012", SNumber 8), ("%M0014", SNumber 3)]
              , obVars = M.fromList [("P.X", SNumber 6)]
              , obOutputs = M.fromList [("OUTPUT2", False)]
              , obError = Just (ErrorReport (Just 2015) Nothing (Just 3) Nothing)
              }
      judge ex answer
        `shouldBe` Fail
          ( Difference "verdict" "ok" "runtime-error (error 2015 at line 3)"
              :| [ Difference "error" "none" "error 2015 at line 3"
                 , Difference "%M0012" "7" "8"
                 , Difference "%M0013" "1" "not reported"
                 , Difference "P.X" "5" "6"
                 , Difference "OUTPUT2" "true" "false"
                 ]
          )
    it "a rejection at another line and of another kind gives both differences" $
      judge emptyExpect {exVerdict = Just ExpRejected, exReject = Just (ExpReject (Just 5) (Just "undeclared-variable"))} (AnswerRejected (Just 6) (Just "type-mismatch") "m")
        `shouldBe` Fail (Difference "reject.line" "5" "6 (m)" :| [Difference "reject.kind" "undeclared-variable" "type-mismatch (m)"])

  describe "shards and filters" $ do
    it "every case index is in exactly one of N shards" $
      [length [i | i <- [1 .. 4], inShard (Just (i, 4)) k] | k <- [0 .. 20]] `shouldBe` replicate 21 1
    it "globs: * crosses /, ? is one character" $ do
      globMatch "mastertool-xe/*/int-*" "mastertool-xe/arith/int-add" `shouldBe` True
      globMatch "*saturates" "mastertool-xe/arith/int-add-saturates" `shouldBe` True
      globMatch "mastertool-xe/arit?" "mastertool-xe/arith" `shouldBe` True
      globMatch "mastertool-xe/arith" "mastertool-xe/arith/x" `shouldBe` False
  where
    isFail = \case
      Fail _ -> True
      _ -> False
