-- | The large modules of the parsing and checking benchmarks: generated
-- valid procedure modules of a chosen number of lines, and the work timed on
-- them.
module BigModule
  ( generate
  , parseAndCheck
  , moduleLines
  ) where

import qualified Data.Text as T
import Stref.Check (checkModule)
import Stref.Checked
import Stref.Policy (mastertoolXE)
import Stref.Syntax.Parser (parseModule)

-- | The statement lines of the four modules: about 128 KB, 256 KB, 512 KB
-- and 1 MB.
moduleLines :: [Int]
moduleLines = [2375, 4750, 9500, 19000]

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
