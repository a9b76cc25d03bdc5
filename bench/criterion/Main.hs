-- | Parsing, and parsing with checking, of the large generated modules
-- (128 KB to 1 MB), measured by criterion: its statistics (mean, standard
-- deviation, outlier effect) per size. `bench/parse-check` gives the same
-- work as a pass/fail check of the 1 MB target.
--
--   stack bench stref:bench:parse-check-criterion
--   stack bench stref:bench:parse-check-criterion --ba '--output report.html'
module Main (main) where

import Control.Exception (evaluate)
import Criterion.Main
import qualified Data.Text as T
import BigModule
import Stref.Policy (mastertoolXE)
import Stref.Syntax.Parser (parseModule)

-- | Parse only; 1 for a parsed module (the parser decides only at the end).
parseOnly :: T.Text -> Int
parseOnly src = either (const 0) (const 1) (parseModule mastertoolXE "big.st" src)

main :: IO ()
main = do
  sources <- mapM (\n -> evaluate (generate n) >>= \src -> evaluate (T.length src) >> pure (n, src)) moduleLines
  let label src = show (T.length src `div` 1024) ++ " KB"
  defaultMain
    [ bgroup "parse" [bench (label src) (nf parseOnly src) | (_, src) <- sources]
    , bgroup "parse+check" [bench (label src) (nf parseAndCheck src) | (_, src) <- sources]
    ]
