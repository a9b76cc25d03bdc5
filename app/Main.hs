module Main (main) where
import qualified Stref
main :: IO ()
main = putStrLn Stref.version
