module ConformanceProtocolSpec (spec) where

import Data.Aeson (decode, encode)
import qualified Data.Map.Strict as M
import Data.Word (Word32)
import Stref.Conformance.Protocol
import Stref.Values (realBits, realFromBits)
import Test.Hspec
import Test.QuickCheck

spec :: Spec
spec = describe "Conformance protocol stref-engine/1" $ do
  it "a binary32 survives the trip through JSON text, bit for bit" $
    property $ \(w :: Word32) ->
      let f = realFromBits w
          back = decode (encode (scalarFromFloat f)) >>= scalarToFloat
       in case back of
            Just g -> if isNaN f then isNaN g else realBits g == w
            Nothing -> False

  it "finite values travel as numbers, -0.0 and infinities as bits" $ do
    encode (scalarFromFloat 0.1) `shouldBe` "0.1"
    encode (scalarFromFloat (-0.0)) `shouldBe` "{\"bits\":\"0x80000000\"}"
    encode (scalarFromFloat (1 / 0)) `shouldBe` "{\"bits\":\"0x7F800000\"}"

  it "a huge exponent in an answer does not build a huge number" $ do
    (decode "1e1000000000" >>= scalarToFloat) `shouldBe` Just (1 / 0)
    (decode "1e1000000000" >>= \case SNumber n -> Just (smallInteger n); _ -> Nothing) `shouldBe` Just Nothing

  it "reads the answers of the contract" $ do
    decode "{\"verdict\": \"ok\", \"operands\": {\"%M0012\": 32767, \"%M0013.0\": true}, \"outputs\": {\"OUTPUT1\": true}, \"error\": null}"
      `shouldBe` Just (AnswerRun VerdictOk emptyObservation {obOperands = M.fromList [("%M0012", SNumber 32767), ("%M0013.0", SBool True)], obOutputs = M.fromList [("OUTPUT1", True)]})
    decode "{\"verdict\": \"runtime-error\", \"error\": {\"code\": 2020, \"line\": 10, \"comp\": [0, 0, 0]}, \"operands\": {}}"
      `shouldBe` Just (AnswerRun VerdictRuntimeError emptyObservation {obError = Just (ErrorReport (Just 2020) Nothing (Just 10) (Just (0, 0, 0)))})
    decode "{\"verdict\": \"rejected\", \"line\": 5, \"message\": \"Variable X was not declared.\"}"
      `shouldBe` Just (AnswerRejected (Just 5) Nothing "Variable X was not declared.")
    decode "{\"verdict\": \"unsupported\", \"reason\": \"INTERNAL_OVERFLOW\"}"
      `shouldBe` Just (AnswerUnsupported "INTERNAL_OVERFLOW")

  it "refuses an unknown verdict" $
    (decode "{\"verdict\": \"maybe\"}" :: Maybe Answer) `shouldBe` Nothing

  it "answers round-trip" $
    forM' [ AnswerRun VerdictOk emptyObservation {obVars = M.fromList [("P.X", SNumber 3)]}
          , AnswerRejected (Just 7) (Just "undeclared-variable") "m"
          , AnswerUnsupported "r"
          ] $ \a -> decode (encode a) `shouldBe` Just a
  where
    forM' xs f = mapM_ f xs
