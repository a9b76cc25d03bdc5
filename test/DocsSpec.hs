-- | The documents stand on their own: every file of the repository that the
-- README and docs/ name exists at the path shown, and none sends the reader
-- outside the checkout (the project's working material, a machine's paths).
module DocsSpec (spec) where

import Control.Monad (filterM, forM)
import Data.Char (isAlphaNum, isUpper)
import Data.List (isInfixOf, isPrefixOf)
import System.Directory (doesPathExist, listDirectory)
import System.FilePath (splitDirectories, takeDirectory, takeExtension, (</>))
import Test.Hspec

-- | The documents a reader follows.
documents :: IO [FilePath]
documents = do
  docs <- map ("docs" </>) . filter ((== ".md") . takeExtension) <$> listDirectory "docs"
  pure (["README.md", "conformance/README.md", "bench/README.md", "conformance/engines/example/README.md", "docs/ci/README.md"] ++ docs)

-- | Words that look like a path into the repository: starting at one of its
-- top directories, ending in a file name with an extension.
citedPaths :: String -> [String]
citedPaths text =
  [ p
  | w <- words (map (\c -> if pathChar c then c else ' ') text)
  , let p = trimEnd w
  , any (`isPrefixOf` p) ["src/", "app/", "test/", "bench/", "docs/", "conformance/", "scripts/"]
  , '.' `elem` dropWhile (/= '/') p
  , not (any (`isInfixOf` p) ["...", "<", "*", "bench/out/"])
  , not (any placeholder (splitDirectories p))
  ]
  where
    -- bench/programs/NAME.c: a name to fill in
    placeholder part = let base = takeWhile (/= '.') part in length base > 1 && all isUpper base
    pathChar c = isAlphaNum c || c `elem` ("/._-<>*" :: String)
    trimEnd = reverse . dropWhile (`elem` ("./" :: String)) . reverse

spec :: Spec
spec = describe "the documentation" $ do
  it "names only files that exist at the paths shown" $ do
    docs <- documents
    missing <- fmap concat . forM docs $ \d -> do
      text <- readFile d
      let candidates p = [p, takeDirectory d </> p]
      fmap (map (\p -> d ++ ": " ++ p)) . filterM (fmap not . anyExists . candidates) $ citedPaths text
    missing `shouldBe` []
  it "sends the reader to nothing outside the checkout" $ do
    docs <- documents
    outside <- fmap concat . forM docs $ \d -> do
      text <- readFile d
      pure [d ++ ": " ++ l | l <- lines text, any (`isInfixOf` l) ["shared/spec", "shared/seeds", "../shared", "/root/", "/home/", "/work/"]]
    outside `shouldBe` []
  where
    anyExists = fmap or . mapM doesPathExist
