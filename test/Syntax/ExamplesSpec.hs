-- | The manual's example programs (test/examples, transcribed and repaired
-- as their header comments say) and every .st file of the corpus: each
-- parses, and its normalised print parses back to the same tree.
module Syntax.ExamplesSpec (spec) where

import Control.Monad (filterM, forM_)
import qualified Data.ByteString as BS
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Encoding.Error as TE
import Data.Ratio ((%))
import Stref.Policy
import Stref.Syntax
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
    , "mapping_declarations", "variable_list"
    ]

checkFile :: FilePath -> Expectation
checkFile file = do
  bytes <- BS.readFile file
  let source = TE.decodeUtf8With TE.lenientDecode bytes
  case parseModule mastertoolXE file source of
    Left e
      -- a corpus case whose verdict is "rejected" may be a syntax error
      | declaresRejected source -> pure ()
      | otherwise -> expectationFailure (file ++ ": " ++ show e)
    Right m -> do
      let printed = prettyModule m
      fmap (() <$) (parseModule mastertoolXE (file ++ " (printed)") printed) `shouldBe` Right (() <$ m)

-- | Does the case's metadata (the first comment, see the corpus format) say
-- @verdict: rejected@?
declaresRejected :: T.Text -> Bool
declaresRejected source =
  let metadata = fst (T.breakOn "---*)" (snd (T.breakOn "(*---" source)))
   in any ((== "verdict: rejected") . T.strip) (T.lines metadata)

parseExample :: String -> IO (Module ())
parseExample n = do
  let file = "test" </> "examples" </> n <.> "st"
  bytes <- BS.readFile file
  case parseModule mastertoolXE file (TE.decodeUtf8With TE.lenientDecode bytes) of
    Left e -> fail (file ++ ": " ++ show e)
    Right m -> pure (() <$ m)

spec :: Spec
spec = do
  describe "what the manual examples contain" $ do
    it "filter: global constants 0.1 and 0.02, FILTRAR with two inputs, three calls" $ do
      m <- parseExample "filter_p_module"
      map vbConstant (modGlobals m) `shouldBe` [True]
      map vdInit (concatMap vbDecls (modGlobals m))
        `shouldBe` [Just (InitExpr (ELit () (LReal (1 % 10)))), Just (InitExpr (ELit () (LReal (2 % 100))))]
      map fnName (modFunctions m) `shouldBe` [Ident "FILTRAR"]
      length (prBody (modProgram m)) `shouldBe` 3
    it "event buffer: table position %TM0010[000] and bit %A0001.0" $ do
      m <- parseExample "event_buffer"
      [op | Just (_, op) <- map vdAt (concatMap vbDecls (modGlobals m))]
        `shouldBe` [OperandRef "TM" 10 (Position 0), OperandRef "M" 0 NoSub, OperandRef "M" 1 NoSub, OperandRef "M" 2 NoSub, OperandRef "A" 1 (BitOf 0)]
      prBody (modProgram m)
        `shouldBe` [ CallStmt () (Ident "INSERIR_VALOR") [EBinary () Add (EBinary () Mul (EVar () (Ident "MINUTO")) (ELit () (LInt 256 10))) (EVar () (Ident "SEGUNDO"))]
                   , CallStmt () (Ident "INSERIR_VALOR") [EVar () (Ident "HORA")]
                   , CallStmt () (Ident "INSERIR_VALOR") [EVar () (Ident "EVENTO")]
                   ]
    it "IF example: four tests (ELSEIF read as ELSIF) and an ELSE" $ do
      m <- parseExample "if_elseif"
      case prBody (modProgram m) of
        [If () branches (Just [_])] -> length branches `shouldBe` 4
        other -> expectationFailure (show other)
    it "temperature table (EN): the constant END is an ordinary name (A30)" $ do
      m <- parseExample "temperature_table_en"
      [n | b <- prBlocks (modProgram m), vbConstant b, d <- vbDecls b, (_, Ident n) <- vdNames d] `shouldBe` ["START", "END"]
    it "TESTE: the only statement is the empty statement" $ do
      m <- parseExample "f_module_parameters"
      prBody (modProgram m) `shouldBe` [Empty ()]
      map vbSection (prBlocks (modProgram m)) `shouldBe` [SecInput, SecInOut, SecOutput]
  describe "manual examples" $
    forM_ manualExamples $ \f -> it (takeBaseName f ++ " parses and round-trips") (checkFile f)
  describe "every .st file of test/examples and the MasterTool XE corpus" $ do
    -- the list is read when the spec tree is built; the directories are
    -- part of the repository (the IEC dialects' cases have their own
    -- parser: test/IEC/ParserSpec.hs)
    let files = unsafePerformIO (concat <$> mapM stFilesUnder ["test" </> "examples", "conformance" </> "mastertool-xe"])
    it "finds the manual examples" $ length files `shouldSatisfy` (>= length manualExamples)
    forM_ files $ \f -> it (f ++ " parses and round-trips") (checkFile f)
