-- | The manual's example programs (test/examples, transcribed and repaired
-- as their header comments say) and every .st file of the corpus: each
-- parses, and its normalised print parses back to the same tree.
module Syntax.ExamplesSpec (spec) where

import Control.Monad (filterM, forM_)
import qualified Data.ByteString as BS
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Encoding.Error as TE
import Stref.Policy
import Stref.Syntax.Parser
import Stref.Syntax.Pretty
import System.Directory
import System.FilePath
import System.IO.Unsafe (unsafePerformIO)
import Test.Hspec

-- | All .st files below a directory (none if it does not exist).
stFilesUnder :: FilePath -> IO [FilePath]
stFilesUnder dir = do
  exists <- doesDirectoryExist dir
  if not exists
    then pure []
    else do
      entries <- map (dir </>) <$> listDirectory dir
      dirs <- filterM doesDirectoryExist entries
      nested <- concat <$> mapM stFilesUnder dirs
      pure ([f | f <- entries, takeExtension f == ".st"] ++ nested)

-- | The expected set of manual examples: a missing file is a failure.
manualExamples :: [FilePath]
manualExamples =
  map (\n -> "test" </> "examples" </> n <.> "st")
    [ "filter_p_module", "filter_f_module", "filter_en_p_module", "filter_en_f_module"
    , "sum_signals", "sum_en_signals", "sum_overflow_return", "sum_en_overflow_return"
    , "expt", "array_initialiser", "var_constant", "f_module_parameters", "f_module_declaration"
    , "function_declaration", "bitwise_byte", "if_elseif", "case", "while", "repeat", "for"
    , "status_machine", "event_buffer", "temperature_table", "temperature_table_en"
    ]

checkFile :: FilePath -> Expectation
checkFile file = do
  bytes <- BS.readFile file
  let source = TE.decodeUtf8With TE.lenientDecode bytes
  case parseModule mastertoolXE file source of
    Left e -> expectationFailure (file ++ ": " ++ show e)
    Right m -> do
      let printed = prettyModule m
      fmap (() <$) (parseModule mastertoolXE (file ++ " (printed)") printed) `shouldBe` Right (() <$ m)

spec :: Spec
spec = do
  describe "manual examples" $
    forM_ manualExamples $ \f -> it (takeBaseName f ++ " parses and round-trips") (checkFile f)
  describe "every .st file of test/examples and conformance" $ do
    -- the list is read when the spec tree is built; the directories are
    -- part of the repository
    let files = unsafePerformIO (concat <$> mapM stFilesUnder ["test" </> "examples", "conformance"])
    it "finds the manual examples" $ length files `shouldSatisfy` (>= length manualExamples)
    forM_ files $ \f -> it (f ++ " parses and round-trips") (checkFile f)
