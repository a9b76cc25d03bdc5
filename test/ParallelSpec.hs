-- | The workers that load and run the corpus ('inParallel').
module ParallelSpec (spec) where

import Control.Exception (ErrorCall (..), evaluate, throwIO, try)
import Data.IORef (atomicModifyIORef', newIORef, readIORef)
import Stref.Conformance.Parallel (inParallel)
import Test.Hspec
import Test.QuickCheck
import Test.QuickCheck.Monadic (monadicIO, run)

spec :: Spec
spec = describe "inParallel" $ do
  it "gives each element's result in the order of the elements, for any number of workers" $
    property $ \(Positive n) (xs :: [Int]) -> monadicIO $ do
      rs <- run (inParallel (min 8 n) (\x -> evaluate (x * 3 - 1)) xs)
      pure (rs == map (\x -> x * 3 - 1) xs)
  it "runs the action once for each element" $ do
    count <- newIORef (0 :: Int)
    _ <- inParallel 3 (\_ -> atomicModifyIORef' count (\k -> (k + 1, ()))) [1 .. 100 :: Int]
    readIORef count `shouldReturn` 100
  it "passes on an exception of the action" $ do
    r <- try (inParallel 2 (\x -> if x == (7 :: Int) then throwIO (ErrorCall "seven") else pure x) [1 .. 20])
    r `shouldBe` Left (ErrorCall "seven")
