-- | The text pipeline (Stref.Run): operand settings and snippets.
module RunSpec (spec) where

import Data.Either (isLeft)
import Stref.Execution
import Stref.Operands
import Stref.Policy
import Stref.Run
import Stref.Types
import Stref.Values
import Test.Hspec

spec :: Spec
spec = describe "Stref.Run" $ do
  describe "applySetting" $ do
    let written o s = fmap (\m -> readCell m (operandCell o)) (applySetting o s emptyMemory)
    it "writes -1 into a %M as the pattern 16#FFFF" $ written (OpSimple KM 10) (SetInt (-1)) `shouldBe` Right 0xFFFF
    it "writes 65535 into a %M as the same pattern" $ written (OpSimple KM 10) (SetInt 65535) `shouldBe` Right 0xFFFF
    it "rejects 65536 for a %M" $ written (OpSimple KM 10) (SetInt 65536) `shouldSatisfy` isLeft
    it "sets one bit: %M0006.6 := TRUE is 16#0040" $ written (OpBit KM 6 6) (SetBool True) `shouldBe` Right 0x40
    it "rejects a number other than 0/1 for a bit" $ written (OpBit KM 6 6) (SetInt 2) `shouldSatisfy` isLeft
    it "writes 2.5 into a %F as its binary32 pattern" $ written (OpSimple KF 2) (SetReal 2.5) `shouldBe` Right (realBits 2.5)
    it "rejects a real for a %M" $ written (OpSimple KM 1) (SetReal 2.5) `shouldSatisfy` isLeft
  describe "evalSnippet" $ do
    let value t = case evalSnippet mastertoolXE t of
          Right sr -> (srType sr, lookup "EVAL.EVAL_RESULT" (crVars (srResult sr)))
          Left _ -> (Nothing, Nothing)
    it "7 / 2 is INT 3 (truncation, A7)" $ value "7 / 2" `shouldBe` (Just INT, Just (VInt 3))
    it "1.5 * 2.0 is REAL 3.0" $ value "1.5 * 2.0" `shouldBe` (Just REAL, Just (VReal 3.0))
    it "INT_TO_BYTE(5) is BYTE" $ value "INT_TO_BYTE(5)" `shouldBe` (Just BYTE, Just (VByte 5))
    it "TRUE AND FALSE is BOOL FALSE" $ value "TRUE AND FALSE" `shouldBe` (Just BOOL, Just (VBool False))
    it "runs statements with declarations and reports the variables" $
      fmap (\sr -> (lookup "EVAL.I" (crVars (srResult sr)), crOverflow (srResult sr))) (evalSnippet mastertoolXE "VAR I : INT; END_VAR I := 32767 + 1;")
        `shouldSatisfy` either (const False) (== (Just (VInt 32767), True))
    it "reports a rejected snippet" $ evalSnippet mastertoolXE "X := 1;" `shouldSatisfy` isLeft
