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
import Stref.Check (checkModule)
import Stref.Checked
import Stref.Policy (mastertoolXE)
import Stref.Syntax.Parser (parseModule)

-- | A valid procedure module with about @n@ statement lines in its program.
generate :: Int -> T.Text
generate n = T.concat (header : map function [0 .. functions - 1] ++ [program] ++ concatMap line [0 .. n - 1] ++ [footer])
  where
    functions = 100 :: Int
    header = "VAR\n  RESULT AT %M0100 : INT;\nEND_VAR\n"
    function f =
      T.pack $
        "FUNCTION F" ++ show f ++ " : INT\nVAR_INPUT\n  A, B : INT;\nEND_VAR\nVAR\n  T : INT;\nEND_VAR\n"
          ++ "T := A * 3 + B;\nIF T > 100 THEN\n  T := T - 100;\nELSE\n  T := T + 1;\nEND_IF;\nF" ++ show f ++ " := T;\nEND_FUNCTION\n"
    program = "PROGRAM BIG\nVAR\n  X, Y : INT;\n  I : INT;\n  V : ARRAY[0..99] OF DINT;\nEND_VAR\n"
    line k =
      [T.pack ("X := X + " ++ show (k `mod` 1000) ++ " * 3 - (Y MOD 7); (* line " ++ show k ++ " *)\n")]
        ++ [T.pack "FOR I := 0 TO 99 DO V[I] := V[I] + INT_TO_DINT(X); END_FOR;\n" | k `mod` 10 == 0]
        ++ [T.pack ("Y := F" ++ show ((k `div` 20) `mod` functions) ++ "(X, " ++ show (k `mod` 100) ++ ");\n") | k `mod` 20 == 0]
    footer = "RESULT := X;\nEND_PROGRAM\n"

-- | Parse and check; the size of the checked program, so that it is built.
{-# NOINLINE parseAndCheck #-}
parseAndCheck :: T.Text -> Either String Int
parseAndCheck src = case parseModule mastertoolXE "big.st" src of
  Left e -> Left (show e)
  Right m -> case checkModule mastertoolXE ProcedureModule m of
    Left es -> Left (show (take 1 es))
    Right cm -> Right (if cm == cm then length (cpBody (cmProgram cm)) + length (cmFunctions cm) else 0)

main :: IO ()
main = do
  printf "%10s %10s %12s %12s %12s\n" ("size (KB)" :: String) ("lines" :: String) ("CPU (ms)" :: String) ("wall (ms)" :: String) ("CPU us/KB" :: String)
  results <- forM [2375, 4750, 9500, 19000] $ \n -> do
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
