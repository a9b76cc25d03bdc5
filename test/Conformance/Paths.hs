-- | Where the conformance tests find their fixtures and the built @stref@.
module Conformance.Paths
  ( fixtureCorpus
  , malformedCorpus
  , engineScript
  , strefBinary
  ) where

import Control.Monad (filterM, forM)
import Data.List (sortOn)
import Data.Ord (Down (..))
import System.Directory
import System.Environment (lookupEnv)
import System.FilePath

fixtureCorpus, malformedCorpus :: FilePath
fixtureCorpus = "test" </> "fixtures" </> "conformance"
malformedCorpus = "test" </> "fixtures" </> "malformed"

-- | A shell command that runs one of the scripts in test/engines.
engineScript :: String -> String
engineScript name = "sh " ++ ("test" </> "engines" </> name ++ ".sh")

-- | The @stref@ executable: @STREF_BIN@ if set, else the newest one that
-- stack built in this package (the test suite runs in the package
-- directory; stack builds the executable before it runs the tests).
strefBinary :: IO FilePath
strefBinary = do
  env <- lookupEnv "STREF_BIN"
  case env of
    Just p -> pure p
    Nothing -> do
      candidates <- concat <$> mapM (globs ".stack-work") [["dist", "*", "*", "build", "stref", "stref"], ["install", "*", "*", "*", "bin", "stref"]]
      existing <- filterM doesFileExist candidates
      timed <- forM existing $ \p -> (,p) <$> getModificationTime p
      case sortOn (Down . fst) timed of
        ((_, p) : _) -> pure p
        [] -> fail "cannot find the stref executable: build it (stack build) or set STREF_BIN"
  where
    globs dir [] = pure [dir]
    globs dir ("*" : rest) = do
      ok <- doesDirectoryExist dir
      if not ok
        then pure []
        else do
          names <- listDirectory dir
          concat <$> mapM (\n -> globs (dir </> n) rest) names
    globs dir (n : rest) = globs (dir </> n) rest
