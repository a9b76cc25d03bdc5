-- | The command line as a user meets it: the built executable, its exit codes
-- (0 success, 1 a negative answer, 2 a usage error) and its output formats.
-- Expected values come from the rules, not from earlier runs: 15000 + 25000
-- on INT saturates to 32767 with INTERNAL_OVERFLOW (MT-OP-6, MT-OP-7); a
-- division by zero is runtime error 2020 at the line of the division
-- (MT-OP-9, MT-DIAG-2); a successful call leaves [-32768, 0, 0, 0, 0] in the
-- diagnostic band (MT-DIAG-4).
module CliSpec (spec) where

import Conformance.Paths (strefBinary)
import Data.Aeson (Value (..), decode)
import qualified Data.Aeson.Key as Key
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (isInfixOf)
import qualified Data.Vector as V
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.Process (readProcessWithExitCode)
import Test.Hspec

fixture :: FilePath -> FilePath
fixture name = "test" </> "fixtures" </> "cli" </> name

stref :: [String] -> IO (ExitCode, String, String)
stref args = do
  bin <- strefBinary
  readProcessWithExitCode bin args ""

-- | A field of a JSON object, following a path of keys.
field :: [String] -> Value -> Maybe Value
field [] v = Just v
field (k : ks) (Object o) = KM.lookup (Key.fromString k) o >>= field ks
field _ _ = Nothing

spec :: Spec
spec = describe "the stref command line" $ do
  it "prints its version" $ do
    (code, out, _) <- stref ["--version"]
    code `shouldBe` ExitSuccess
    out `shouldSatisfy` ("stref " `isInfixOf`)

  it "exits 2 without a command" $ do
    (code, _, _) <- stref []
    code `shouldBe` ExitFailure 2

  describe "parse" $ do
    it "prints a valid module normalised and exits 0" $ do
      (code, out, _) <- stref ["parse", fixture "sat.st"]
      code `shouldBe` ExitSuccess
      lines out `shouldContain` ["PROGRAM SAT", "  R := A + B;", "  OV := INTERNAL_OVERFLOW;", "END_PROGRAM"]
    it "reports a syntax error with file, line, column and a caret, and exits 1" $ do
      (code, out, err) <- stref ["parse", fixture "syntax-error.st"]
      code `shouldBe` ExitFailure 1
      let text = out ++ err
      text `shouldSatisfy` ("syntax-error.st:3:8: error:" `isInfixOf`)
      text `shouldSatisfy` ("[unexpected-after]" `isInfixOf`)
      text `shouldSatisfy` ("           ^" `isInfixOf`)
    it "exits 2 for a file that does not exist" $ do
      (code, _, _) <- stref ["parse", fixture "no-such-file.st"]
      code `shouldBe` ExitFailure 2

  describe "check" $ do
    it "exits 0 for a valid module" $ do
      (code, _, _) <- stref ["check", fixture "sat.st"]
      code `shouldBe` ExitSuccess
    it "reports an undeclared variable in text and exits 1" $ do
      (code, out, err) <- stref ["check", fixture "undeclared.st"]
      code `shouldBe` ExitFailure 1
      (out ++ err) `shouldSatisfy` ("undeclared.st:3:6: error:" `isInfixOf`)
      (out ++ err) `shouldSatisfy` ("[undeclared-variable]" `isInfixOf`)
    it "reports the same error as JSON" $ do
      (code, out, _) <- stref ["check", fixture "undeclared.st", "--format", "json"]
      code `shouldBe` ExitFailure 1
      let j = decode (BL.pack out) :: Maybe Value
          firstError = j >>= field ["errors"] >>= \case
            Array a | not (V.null a) -> Just (V.head a)
            _ -> Nothing
      (j >>= field ["valid"]) `shouldBe` Just (Bool False)
      (firstError >>= field ["kind"]) `shouldBe` Just (String "undeclared-variable")
      (firstError >>= field ["line"]) `shouldBe` Just (Number 3)
      (firstError >>= field ["column"]) `shouldBe` Just (Number 6)
    it "reports it in gcc format" $ do
      (code, out, err) <- stref ["check", fixture "undeclared.st", "--format", "gcc"]
      code `shouldBe` ExitFailure 1
      (out ++ err) `shouldSatisfy` ("undeclared.st:3:6: error:" `isInfixOf`)
    it "exits 2 for an unknown policy" $ do
      (code, _, err) <- stref ["check", fixture "sat.st", "--policy", "overflow=sideways"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("saturate" `isInfixOf`)

  describe "run" $ do
    it "saturates INT addition and reports it as JSON" $ do
      (code, out, _) <- stref ["run", fixture "sat.st", "--set", "%M0010=15000", "--set", "%M0011=25000", "--format", "json"]
      code `shouldBe` ExitSuccess
      let j = decode (BL.pack out) :: Maybe Value
      (j >>= field ["operands", "%M0012"]) `shouldBe` Just (Number 32767)
      (j >>= field ["outputs", "OUTPUT1"]) `shouldBe` Just (Bool True)
      (j >>= field ["diagnostics"]) `shouldBe` Just (Array (V.fromList (map Number [-32768, 0, 0, 0, 0])))
    it "wraps under --policy overflow=wrap" $ do
      (code, out, _) <- stref ["run", fixture "sat.st", "--set", "%M0010=15000", "--set", "%M0011=25000", "--format", "json", "--policy", "overflow=wrap"]
      code `shouldBe` ExitSuccess
      -- 40000 - 65536 = -25536
      (decode (BL.pack out) >>= field ["operands", "%M0012"]) `shouldBe` Just (Number (-25536))
    it "stops at a division by zero with error 2020 on its line and exits 1" $ do
      (code, out, _) <- stref ["run", fixture "divzero.st", "--set", "%M0010=5", "--format", "json"]
      code `shouldBe` ExitFailure 1
      let j = decode (BL.pack out) :: Maybe Value
      (j >>= field ["diagnostics"]) `shouldBe` Just (Array (V.fromList (map Number [8, 2020, 0, 0, 0])))
      -- the write before the error persists (MT-EXEC-8)
      (j >>= field ["operands", "%M0012"]) `shouldBe` Just (Number 7)
      (j >>= field ["outputs", "OUTPUT1"]) `shouldBe` Just (Bool False)

  describe "eval" $ do
    it "prints the variables and INTERNAL_OVERFLOW" $ do
      (code, out, _) <- stref ["eval", "VAR A, B : INT; END_VAR A := 32767; B := A + 1;"]
      code `shouldBe` ExitSuccess
      lines out `shouldContain` ["B = 32767", "INTERNAL_OVERFLOW = TRUE"]
    it "evaluates a bare expression left to right (MT-OP-17)" $ do
      (code, out, _) <- stref ["eval", "--", "10 - 4 - 3"]
      code `shouldBe` ExitSuccess
      lines out `shouldContain` ["value = 3 : INT"]
    it "compares the alternatives of a policy side by side" $ do
      (code, out, _) <- stref ["eval", "--compare", "overflow", "VAR A : INT; END_VAR A := 32767; A := A + 1;"]
      code `shouldBe` ExitSuccess
      let row = filter (\l -> "* A " `isInfixOf` l) (lines out)
      map words row `shouldBe` [["*", "A", "32767", "-32768", "32767"]]
