module VersionSpec (spec) where
import Test.Hspec
import qualified Stref
spec :: Spec
spec = it "has a version" $ Stref.version `shouldBe` "0.1.0"
