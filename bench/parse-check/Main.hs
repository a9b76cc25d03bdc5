-- | Parsing and checking time against module size: generated modules of
-- 128 KB to 1 MB (functions, FOR loops, calls, arithmetic), each parsed and
-- checked in process, the best of three runs. Prints the CPU and wall time
-- per size and the CPU time per kilobyte (flat when parsing and checking are
-- linear); fails when the 1 MB module takes a CPU second or more.
--
--   stack bench stref:bench:parse-check
module Main (main) where

import Control.Exception (evaluate)
import Control.Monad (forM, forM_, unless)
import qualified Data.Text as T
import GHC.Clock (getMonotonicTime)
import System.CPUTime (getCPUTime)
import System.Exit (exitFailure)
import Text.Printf (printf)
import BigModule

main :: IO ()
main = do
  printf "%10s %10s %12s %12s %12s\n" ("size (KB)" :: String) ("lines" :: String) ("CPU (ms)" :: String) ("wall (ms)" :: String) ("CPU us/KB" :: String)
  results <- forM moduleLines $ \n -> do
    let src = generate n
    _ <- evaluate (T.length src)
    times <- forM [1 :: Int .. 3] $ \run -> do
      -- a different text for each run (trailing blank lines), so that no
      -- result is shared between runs
      src' <- evaluate (T.append src (T.replicate run "\n"))
      t0 <- getMonotonicTime
      c0 <- getCPUTime
      r <- evaluate (parseAndCheck src')
      case r of
        Left e -> putStrLn ("the generated module is rejected: " ++ e) >> exitFailure
        Right size -> () <$ evaluate size
      c1 <- getCPUTime
      t1 <- getMonotonicTime
      pure (fromIntegral (c1 - c0) / 1e12 :: Double, t1 - t0)
    let cpu = minimum (map fst times)
        wall = minimum (map snd times)
        kb = fromIntegral (T.length src) / 1024 :: Double
    printf "%10.0f %10d %12.1f %12.1f %12.1f\n" kb (length (T.lines src)) (cpu * 1000) (wall * 1000) (cpu * 1e6 / kb)
    pure (kb, cpu)
  forM_ (lastOf results) $ \(kb, t) ->
    unless (kb < 1000 || t < 1) $ putStrLn "a 1 MB module takes a CPU second or more" >> exitFailure
  where
    lastOf xs = [last xs | not (null xs)]
