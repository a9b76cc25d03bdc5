-- | The compatibility matrix: its data, and its page read by a real
-- headless browser (Debian's chromium, which scripts/setup installs; the
-- browser tests are skipped where it is missing).
module Engines.MatrixSpec (spec) where

import Control.Monad (forM_)
import qualified Data.Aeson as A
import qualified Data.Aeson.KeyMap as KM
import Data.List.NonEmpty (NonEmpty (..))
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Matrix
import Stref.Conformance.Runner (CaseResult (..), Difference (..), Outcome (..))
import System.Directory (findExecutable, getFileSize, getTemporaryDirectory, removeFile)
import System.FilePath ((</>))
import System.IO (hClose, openTempFile)
import System.Process (readProcessWithExitCode)
import Test.Hspec

result :: Text -> Outcome -> CaseResult
result i o = CaseResult i ("conformance/" <> T.unpack i <> ".st") Nothing o False 0 Nothing

-- | Two engines, two areas; alpha passes 3 of 5 cases, beta 2.
runs :: [MatrixRun]
runs =
  [ MatrixRun "alpha" "Alpha engine" "1.0" "tecomat" $
      [ result "tecomat/strings/a" Pass
      , result "tecomat/strings/b" (Fail (Difference "MAIN.x" "1" "2" :| []))
      , result "tecomat/statements/c" Pass
      , result "tecomat/statements/d" Pass
      , result "tecomat/statements/e" (Unsupported "resets")
      ]
  , MatrixRun "beta" "Beta engine" "2.0" "tecomat" $
      [ result "tecomat/strings/a" (Fail (Difference "verdict" "ok" "rejected at line 3: <bad> & \"odd\"" :| []))
      , result "tecomat/strings/b" Pass
      , result "tecomat/statements/c" (EngineError "crashed </script>")
      , result "tecomat/statements/d" Pass
      , result "tecomat/statements/e" (Fail (Difference "MAIN.y" "T#1s" "T#0ms" :| []))
      ]
  ]

dataValue :: A.Value
dataValue = matrixData "2026-11-27" "abc1234" (M.fromList [("TC-STMT-1", "statements end with ;")]) runs

spec :: Spec
spec = describe "the compatibility matrix" $ do
  it "its data counts each run's results" $ do
    let totalsOf e = case dataValue of
          A.Object o | Just (A.Array rs) <- KM.lookup "runs" o ->
            [t | A.Object r <- foldr (:) [] rs, KM.lookup "engine" r == Just (A.String e), Just t <- [KM.lookup "totals" r]]
          _ -> []
    totalsOf "alpha" `shouldBe` [A.object ["passed" A..= (3 :: Int), "failed" A..= (1 :: Int), "unsupported" A..= (1 :: Int), "engine-error" A..= (0 :: Int), "skipped" A..= (0 :: Int)]]
    totalsOf "beta" `shouldBe` [A.object ["passed" A..= (2 :: Int), "failed" A..= (2 :: Int), "unsupported" A..= (0 :: Int), "engine-error" A..= (1 :: Int), "skipped" A..= (0 :: Int)]]
  it "its page embeds the data so that no text of a case ends the script" $ do
    let page = matrixPage dataValue
    T.count "</script>" page `shouldBe` 2
    page `shouldSatisfy` T.isInfixOf "crashed <\\/script>"
  describe "in a headless browser" $ do
    it "shows the data's counts for every run" $ withPage $ \dom -> do
      forM_ [("alpha / tecomat", [("pass", 3), ("fail", 1), ("unsupported", 1), ("engine-error", 0)]), ("beta / tecomat", [("pass", 2), ("fail", 2), ("unsupported", 0), ("engine-error", 1)])] $ \(run, counts) ->
        forM_ counts $ \(kind, n :: Int) -> cell dom run kind `shouldBe` Just (T.pack (show n))
      dom `shouldSatisfy` T.isInfixOf "5 cases that did not pass"
    it "filters by engine and area, as a link's #engine=...&area=... chooses" $ withPageAt "#engine=beta&area=tecomat/statements" $ \dom -> do
      cell dom "alpha / tecomat" "pass" `shouldBe` Nothing
      cell dom "beta / tecomat" "pass" `shouldBe` Just "1"
      cell dom "beta / tecomat" "fail" `shouldBe` Just "1"
      dom `shouldSatisfy` T.isInfixOf "2 cases that did not pass"
      dom `shouldSatisfy` T.isInfixOf "data-case=\"tecomat/statements/e\""
      dom `shouldNotSatisfy` T.isInfixOf "data-case=\"tecomat/strings/a\""
    it "renders to a picture (a screenshot to look at)" $ withBrowser $ \chromium file -> do
      tmp <- getTemporaryDirectory
      let png = tmp </> "stref-matrix.png"
      _ <- readProcessWithExitCode chromium (headless ++ ["--window-size=1200,900", "--screenshot=" <> png, "file://" <> file]) ""
      size <- getFileSize png
      size `shouldSatisfy` (> 10000)
  where
    headless = ["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]
    withPage = withPageAt ""
    withPageAt hash check = withBrowser $ \chromium file -> do
      (_, out, _) <- readProcessWithExitCode chromium (headless ++ ["--dump-dom", "file://" <> file <> hash]) ""
      check (T.pack out)
    withBrowser act = do
      found <- findExecutable "chromium"
      case found of
        Nothing -> pendingWith "skipped: no chromium on PATH (scripts/setup installs it)"
        Just chromium -> do
          tmp <- getTemporaryDirectory
          (file, h) <- openTempFile tmp "stref-matrix.html"
          hClose h
          TIO.writeFile file (matrixPage dataValue)
          _ <- act chromium file
          removeFile file
    -- the count in a run's totals row
    cell :: Text -> Text -> Text -> Maybe Text
    cell dom run kind =
      let marker = "data-run=\"" <> run <> "\" data-kind=\"" <> kind <> "\">"
       in case T.breakOn marker dom of
            (_, rest) | not (T.null rest) -> Just (T.takeWhile (/= '<') (T.drop (T.length marker) rest))
            _ -> Nothing
