-- | Runs every *Spec module (found by hspec-discover) and ends with the plain
-- summary line "N passed, N failed" that CI reads.
module Main (main) where

import qualified AllSpecs
import Control.Monad (unless)
import System.Exit (exitFailure)
import Test.Hspec.Runner

main :: IO ()
main = do
  summary <- hspecWithResult defaultConfig AllSpecs.spec
  let failed = summaryFailures summary
      passed = summaryExamples summary - failed
  putStrLn (show passed ++ " passed, " ++ show failed ++ " failed")
  unless (failed == 0) exitFailure
