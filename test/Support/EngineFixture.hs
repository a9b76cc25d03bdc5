-- | What the adapters' tests share: a recorded case of test/engines/ENGINE
-- as a tecomat request, and the live tests that run the recorded cases
-- through an installed engine (skipped, with the reason, without one).
module Support.EngineFixture
  ( fixtureCase
  , liveTests
  ) where

import Control.Monad (forM_)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Case
import Stref.Conformance.Protocol (Answer, Request)
import Stref.Conformance.Runner (buildRequest)
import Stref.Engines.Run (answerWith, engineByName, findTools)
import Stref.Policy (tecomat)
import System.FilePath ((<.>), (</>))
import Test.Hspec

-- | The case @NAME.st@ of a fixture directory and its request under tecomat.
fixtureCase :: FilePath -> String -> IO (Case, Request)
fixtureCase dir name = do
  let file = dir </> name <.> "st"
  src <- TIO.readFile file
  c <- either (fail . T.unpack) pure (parseCase file (CaseOrigin ("tecomat/engine/" <> T.pack name) "tecomat" "engine") (const True) src)
  pure (c, buildRequest tecomat c (effectiveExpect tecomat c))

-- | For each recorded case: the installed engine answers as recorded.
liveTests :: T.Text -> String -> [String] -> (String -> IO Request) -> (String -> IO Answer) -> Spec
liveTests engine title cases request recorded =
  describe ("live, with " <> title <> " installed") $
    forM_ cases $ \name ->
      it (name <> ": the engine answers as recorded") $ do
        found <- maybe (pure (Left "no adapter")) findTools (engineByName engine)
        case found of
          Left why -> pendingWith ("skipped: " <> T.unpack why)
          Right tools -> do
            rq <- request name
            live <- answerWith tools rq
            expected <- recorded name
            live `shouldBe` Right expected
