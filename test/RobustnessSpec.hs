-- | Robustness: deep nesting, huge literals, huge arrays, invalid UTF-8,
-- bounded fuzzing, runner inputs and linear time on large files.
module RobustnessSpec (spec) where

import Control.Concurrent (threadDelay)
import Control.Exception (IOException, evaluate, try)
import qualified Data.ByteString as BS
import qualified Data.ByteString.Char8 as BC
import Data.Either (isRight)
import Data.Maybe (isNothing)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import System.CPUTime (getCPUTime)
import System.Mem (performGC)
import System.Directory (doesDirectoryExist, doesPathExist, getTemporaryDirectory, listDirectory, removeFile)
import System.IO (hClose, openTempFile)
import Test.Hspec
import Test.QuickCheck
import Stref.Check (checkModule)
import Stref.Checked (ModuleKind (..))
import Stref.Conformance.Case (CaseOrigin (..), parseCase)
import Stref.Conformance.Runner (runExternal)
import Stref.Diagnostics (RuntimeError (..))
import Stref.Execution (CallResult (..))
import Stref.Fuzz
import Stref.Policy
import Stref.Run
import Stref.Source
import Stref.Syntax (Pos (..), posLine)
import Stref.Syntax.Parser (parseModule)
import Stref.Syntax.Pretty (prettyModule)
import Stref.Values (Value (..))
import Stref.Verification (VerificationError (..), renderError)

program :: Text -> Text -> Text
program decls body = "PROGRAM P\nVAR X : DINT; B : BOOL; R : REAL; " <> decls <> " END_VAR\n" <> body <> "\nEND_PROGRAM\n"

-- | The kind and line of the error, or the variables after one call.
runIt :: Text -> Either (Text, Int) [(Text, Value)]
runIt src = case runSource defaultRunSetup "t.st" src [defaultCallSpec] of
  Left (SyntaxError e) -> Left (veKind e, posLine (vePos e))
  Left (Rejected (e : _)) -> Left (veKind e, posLine (vePos e))
  Left (Rejected []) -> Left ("rejected", 0)
  Left (BadSetting m) -> Left (m, 0)
  Right ro -> case roResults ro of
    [r] | Just (RuntimeError code line _) <- crError r -> Left ("runtime-" <> T.pack (show code), line)
    [r] -> Right (crVars r)
    _ -> Left ("calls", 0)

varOf :: Text -> Either (Text, Int) [(Text, Value)] -> Maybe Value
varOf n = either (const Nothing) (lookup n)

spec :: Spec
spec = do
  describe "Robustness: deep nesting (10,000 levels)" $ do
    let deep = 10000
    it "10,000 nested parentheses are refused with nesting-too-deep on their line" $
      fmap fst (either Just (const Nothing) (runIt (program "" ("X := " <> T.replicate deep "(" <> "1" <> T.replicate deep ")" <> ";"))))
        `shouldBe` Just "nesting-too-deep"
    it "10,000 nested IFs are refused with nesting-too-deep" $
      runIt (program "" (T.replicate deep "IF TRUE THEN " <> "X := 1;" <> T.replicate deep " END_IF;"))
        `shouldSatisfy` either ((== "nesting-too-deep") . fst) (const False)
    it "a chain of 10,000 nested function calls is refused with nesting-too-deep" $
      runIt (program "" ("X := " <> T.replicate deep "ABS(" <> "1" <> T.replicate deep ")" <> ";"))
        `shouldSatisfy` either ((== "nesting-too-deep") . fst) (const False)
    it "10,000 NOTs are refused with nesting-too-deep" $
      runIt (program "" ("B := " <> T.replicate deep "NOT " <> "TRUE;"))
        `shouldSatisfy` either ((== "nesting-too-deep") . fst) (const False)
    it "a left-associative sum of 10,000 ones is parsed, checked and run: 10000" $
      -- 1 + 1 + ... + 1 folds to the left, 10,000 terms: 10000 fits DINT
      varOf "P.X" (runIt (program "" ("X := " <> T.intercalate " + " (replicate deep "1") <> ";")))
        `shouldBe` Just (VDInt 10000)
    it "an IF with 10,000 ELSIF branches runs the matching branch" $
      -- X starts at 0; the branch for 0 sets X to 1000 + 0
      varOf "P.X" (runIt (program "" ("IF X = -1 THEN X := 5;" <> T.concat [" ELSIF X = " <> tshow i <> " THEN X := " <> tshow (1000 + i) <> ";" | i <- [0 .. deep - 1 :: Int]] <> " END_IF;")))
        `shouldBe` Just (VDInt 1000)
    it "10,000 nested comments (nested-comments=yes) are skipped" $ do
      let nesting = either (error . T.unpack) id (setPolicy "nested-comments" "yes" mastertoolXE)
          src = program "" (T.replicate deep "(*" <> T.replicate deep "*)" <> "\nX := 7;")
      fmap (const ()) (parseModule nesting "c.st" src) `shouldBe` Right ()
    it "100,000 statements in sequence run (one step each)" $ do
      let src = program "" (T.replicate 100000 "X := X + 1;\n")
      case runSource defaultRunSetup "t.st" src [defaultCallSpec] of
        Right ro -> map crSteps (roResults ro) `shouldBe` [100000]
        Left _ -> expectationFailure "rejected"

  describe "Robustness: huge literals are refused without computing them" $ do
    let real lit = runIt (program "" ("R := " <> lit <> ";"))
        int lit = runIt (program "" ("X := " <> lit <> ";"))
    it "1E999999999 is an invalid number" $ fmap fst (either Just (const Nothing) (real "1E999999999")) `shouldBe` Just "invalid-symbol"
    it "1.0E999999999 is an invalid number" $ fmap fst (either Just (const Nothing) (real "1.0E999999999")) `shouldBe` Just "invalid-symbol"
    it "1.5E-999999999 is an invalid number" $ fmap fst (either Just (const Nothing) (real "1.5E-999999999")) `shouldBe` Just "invalid-symbol"
    it "a 1000-digit integer is out of the limits of DINT" $
      fmap fst (either Just (const Nothing) (int (T.replicate 1000 "9"))) `shouldBe` Just "value-out-of-limits"
    it "16# with 500 digits is out of the limits of DINT" $
      fmap fst (either Just (const Nothing) (int ("16#" <> T.replicate 500 "F"))) `shouldBe` Just "value-out-of-limits"
    it "every huge literal of the fuzzer ends properly, quickly" $
      mapM_
        ( \lit -> do
            v <- checkInput (Guard 20000000 2000000000) (TE.encodeUtf8 (program "" ("R := " <> lit <> "; X := " <> lit <> ";")))
            v `shouldSatisfy` isFine
        )
        hugeLiterals

  describe "Robustness: the data area bounds arrays" $ do
    it "ARRAY[0..2000000000] is refused (invalid-array-size), nothing allocated" $
      fmap fst (either Just (const Nothing) (runIt (program "A : ARRAY[0..2000000000] OF INT;" "X := 1;"))) `shouldBe` Just "invalid-array-size"
    it "ARRAY[-2147483648..2147483647] is refused" $
      runIt (program "A : ARRAY[-2147483648..2147483647] OF DINT;" "X := 1;") `shouldSatisfy` either (const True) (const False)
    it "an array of 1536 INT (3072 bytes) beside other variables exceeds the 3 KB data area" $
      -- 1536 * 2 bytes = 3072, plus X (4), B (1), R (4) > 3072 (MT-LIM-10)
      runIt (program "A : ARRAY[0..1535] OF INT;" "X := 1;") `shouldSatisfy` either (const True) (const False)

  describe "Robustness: runs are bounded" $ do
    it "WHILE TRUE stops at the step budget with runtime error 2030 on its line" $ do
      let setup = defaultRunSetup {rsPolicies = mastertoolXE {pStepBudget = 5000}}
      case runSource setup "t.st" (program "" "WHILE TRUE DO\nX := X + 1;\nEND_WHILE;") [defaultCallSpec] of
        Right ro -> [fmap (\(RuntimeError c _ _) -> c) (crError r) | r <- roResults ro] `shouldBe` [Just 2030]
        Left _ -> expectationFailure "rejected"

  describe "Robustness: source files must be UTF-8" $ do
    it "a Latin-1 byte is reported with its offset, line and column" $
      -- bytes: A B \n C 0xE9 -> offset 4, line 2, column 2
      decodeSource (BS.pack [0x41, 0x42, 0x0A, 0x43, 0xE9]) `shouldBe` Left (EncodingError 4 2 2 0xE9)
    it "an overlong form, a surrogate and a code point above U+10FFFF are invalid" $ do
      firstInvalidUtf8 (BS.pack [0x41, 0xC0, 0xAF]) `shouldBe` Just 1
      firstInvalidUtf8 (BS.pack [0xED, 0xA0, 0x80]) `shouldBe` Just 0
      firstInvalidUtf8 (BS.pack [0xF4, 0x90, 0x80, 0x80]) `shouldBe` Just 0
      firstInvalidUtf8 (BS.pack [0x41, 0xE2, 0x82]) `shouldBe` Just 1
    it "a byte order mark at the start is dropped" $
      decodeSource (BS.pack [0xEF, 0xBB, 0xBF, 0x41]) `shouldBe` Right "A"
    it "the rendered message names file, line, column and kind" $
      renderEncodingError "a.st" (EncodingError 4 2 2 0xE9)
        `shouldBe` "a.st:2:2: error: the file is not valid UTF-8 text (byte 16#E9 at byte offset 4); save it as UTF-8 or plain ASCII [invalid-encoding]\n"
    it "the validator agrees with the text library on random bytes" $
      property $ \ws -> let b = BS.pack ws in isNothing (firstInvalidUtf8 b) == isRight (TE.decodeUtf8' b)
    it "the validator agrees with the text library on damaged UTF-8" $
      property $ \(s :: String) (i :: Int) (w :: Int) ->
        let b0 = TE.encodeUtf8 (T.pack s)
            k = if BS.null b0 then 0 else i `mod` BS.length b0
            b = BS.take k b0 <> BS.singleton (fromIntegral w) <> BS.drop (k + 1) b0
         in isNothing (firstInvalidUtf8 b) == isRight (TE.decodeUtf8' b)

  describe "Robustness: fuzzing" $ do
    it "classifies invalid UTF-8, random bytes, a syntax error and a run" $ do
      fst (evaluateInput (BS.pack [0xFF])) `shouldBe` InvalidEncoding
      fst (evaluateInput (BS.pack [0x01])) `shouldBe` SyntaxErrorKind "invalid-char"
      fst (evaluateInput "PROGRAM P\nX := ;\nEND_PROGRAM\n") `shouldSatisfy` isSyntaxError
      fst (evaluateInput (TE.encodeUtf8 (program "" "X := 1;"))) `shouldBe` Ran [Nothing, Nothing]
    it "shrinks a failing input to a minimal one" $ do
      -- fails while the input contains the byte 'Z'
      small <- shrinkInput 1000 (pure . BC.elem 'Z') "PROGRAM P\nX := Z + 1;\nEND_PROGRAM\n"
      small `shouldBe` "Z"
    it "the same seed and index give the same input" $
      generateInput ["PROGRAM P X := 1; END_PROGRAM"] (inputRng 7 42)
        `shouldBe` generateInput ["PROGRAM P X := 1; END_PROGRAM"] (inputRng 7 42)
    it "40 nested calls left open are a syntax error, in every dialect, within 400 MB of allocation" $ do
      -- input 10175 of seed 20261128 (VAR ns: and 16 levels): the nexto parser parsed each
      -- failed argument list again as a variable's, 2^n work
      let open = TE.encodeUtf8 ("VAR ns:" <> T.replicate 40 "ABS(")
      v <- checkInput (Guard 30000000 400000000) open
      v `shouldSatisfy` \case
        Fine (SyntaxErrorKind _) -> True
        _ -> False
    it "500 inputs from the corpus and the examples end without an internal error" $ do
      seeds <- seedPrograms
      report <- fuzzCampaign defaultGuard seeds 20261122 0 500 (\_ _ -> pure ())
      fmap (\(i, why, _, small) -> (i, why, small)) (frFailure report) `shouldBe` Nothing
      frRun report `shouldBe` 500

  describe "Robustness: runner inputs" $ do
    let origin = CaseOrigin "x/y" "mastertool-xe" "x"
    it "a case whose metadata is not YAML is refused with its file and line" $
      parseCase "bad.st" origin (const True) "(*---\nexpect: [unclosed\n---*)\nPROGRAM P\nEND_PROGRAM\n"
        `shouldSatisfy` either ("bad.st:" `T.isPrefixOf`) (const False)
    it "a case with an unknown operand is refused with its file" $
      parseCase "bad.st" origin (const True) "(*---\ndescription: d\nrules: [MT-OP-1]\nexpect:\n  operands: {\"%Q0001\": 1}\n---*)\nPROGRAM P\nEND_PROGRAM\n"
        `shouldSatisfy` either (\m -> "bad.st:" `T.isPrefixOf` m && "%Q0001" `T.isInfixOf` m) (const False)
    it "an engine command that does not exist is an engine error" $ do
      r <- runExternal "/nonexistent/engine --x" 10 1000 ""
      r `shouldSatisfy` either ("exited with status 127" `T.isInfixOf`) (const False)
    it "an answer larger than the limit is refused" $ do
      r <- runExternal "yes" 10 100000 ""
      r `shouldSatisfy` either ("exceeds 100000 bytes" `T.isInfixOf`) (const False)
    it "an engine that does not answer in time is killed with its children" $ do
      -- in the system's temporary directory, never in the working tree
      tmp <- getTemporaryDirectory
      (path, h) <- openTempFile tmp "robust-pid"
      hClose h
      r <- runExternal ("sleep 60 & echo $! > " <> path <> "; wait") 1 1000 ""
      r `shouldSatisfy` either ("no answer within" `T.isInfixOf`) (const False)
      pid <- filter (`elem` ['0' .. '9']) . BC.unpack <$> BS.readFile path
      removeQuietly path
      -- SIGKILL takes effect shortly after it is sent; a killed child whose
      -- parent is gone may stay a zombie (state Z) until it is reaped
      alive <- stillRunning (20 :: Int) pid
      (pid, alive) `shouldSatisfy` (\(p, a) -> not (null p) && not a)

  describe "Robustness: linear time on large files" $ do
    it "parsing and checking 1 MB takes at most about twice as long as 500 KB" $ do
      let chunk i =
            "X := X + " <> tshow (i `mod` 1000 :: Int) <> ";\nIF X > 100 THEN B := NOT B; ELSE R := R * 1.5; END_IF;\n"
          sized bytes = program "" (T.concat (takeBytes bytes (map chunk [0 ..])))
          work src = case parseModule mastertoolXE "big.st" src of
            Left e -> error (show e)
            Right m -> either (length . show) (const 0) (checkModule mastertoolXE ProcedureModule m)
      r <- doublingRatio sized T.length work 500000
      r `shouldSatisfy` (< 3)
    it "checking a CASE with 40,000 labels takes at most about twice as long as 20,000" $ do
      let caseOf n = case parseModule mastertoolXE "c.st" (program "" ("CASE X OF\n" <> T.concat [tshow i <> ": X := 1;\n" | i <- [1 .. n :: Int]] <> "END_CASE;")) of
            Left e -> error (show e)
            Right m -> m
          work m = either length (const 0) (checkModule mastertoolXE ProcedureModule m)
      r <- doublingRatio caseOf (length . show) work 20000
      r `shouldSatisfy` (< 3)
    it "the first value a CASE label repeats is the smallest one used before (any ranges)" $
      property $ \(ranges :: [(Int, Int)]) ->
        let norm = [(min a b `mod` 50, min a b `mod` 50 + abs (a - b) `mod` 5) | (a, b) <- take 8 ranges]
            labels = [if lo == hi then tshow lo else tshow lo <> ".." <> tshow hi | (lo, hi) <- norm]
            src = program "" ("CASE X OF\n" <> T.concat [l <> ": X := 1;\n" | l <- labels] <> "END_CASE;")
            -- by hand: for each label, the least of its values used by an earlier one
            expected =
              [ minimum used
              | (k, (lo, hi)) <- zip [0 :: Int ..] norm
              , let used = [v | v <- [lo .. hi], any (\(c, d) -> c <= v && v <= d) (take k norm)]
              , not (null used)
              ]
            reported = case parseModule mastertoolXE "c.st" src of
              Left _ -> Nothing
              Right m -> Just (either (\es -> [T.takeWhile (/= ' ') (T.drop (T.length "the value ") (veMessage e)) | e <- es, veKind e == "case-value-duplicated"]) (const []) (checkModule mastertoolXE ProcedureModule m))
         in not (null norm) ==> reported === Just (map tshow expected)
    it "checking 2000 chained functions (and rendering their errors) takes at most about twice as long as 1000" $ do
      -- each function calls the one before it; none has an input, so each is
      -- reported (function-without-input) and the errors are rendered
      let chainOf n =
            "FUNCTION F0 : INT\nF0 := 1;\nEND_FUNCTION\n"
              <> T.concat ["FUNCTION F" <> tshow i <> " : INT\nF" <> tshow i <> " := F" <> tshow (i - 1) <> "() + 1;\nEND_FUNCTION\n" | i <- [1 .. n - 1 :: Int]]
              <> "PROGRAM P\nVAR X : INT; END_VAR\nX := F0();\nEND_PROGRAM\n"
          work src = case runSource defaultRunSetup "f.st" src [] of
            Left f -> T.length (renderRunFailure "f.st" src f)
            Right _ -> 0
      r <- doublingRatio chainOf T.length work 1000
      r `shouldSatisfy` (< 3)
    it "rendering 2000 errors on one long line takes at most about twice as long as 1000" $ do
      -- every 30-digit literal is out of the limits of DINT: one error each,
      -- all on line 3 (the line is shown clipped around each column)
      let errorsOf n = program "" ("X := " <> T.intercalate " * " (replicate n (T.replicate 30 "9")) <> ";")
          work src = case runSource defaultRunSetup "m.st" src [] of
            Left f -> T.length (renderRunFailure "m.st" src f)
            Right _ -> 0
      r <- doublingRatio errorsOf T.length work 1000
      r `shouldSatisfy` (< 3)
    it "a long source line is shown around the error's column" $
      -- 200 'A's then 'B' at column 201: the window starts 80 before it
      renderError "l.st" (T.replicate 200 "A" <> "B") (VerificationError "k" (Pos 1 201) "m")
        `shouldBe` T.unlines
          [ "l.st:1:201: error: m [k]"
          , "1 | ..." <> T.replicate 80 "A" <> "B"
          , "    " <> T.replicate 83 " " <> "^"
          ]
    it "checking a sum of 40,000 literals takes at most about twice as long as 20,000" $ do
      let sumOf n = case parseModule mastertoolXE "s.st" (program "" ("X := " <> T.intercalate " + " (replicate n "1") <> ";")) of
            Left e -> error (show e)
            Right m -> m
          work m = either length (const 1) (checkModule mastertoolXE ProcedureModule m)
      r <- doublingRatio sumOf (length . show) work 20000
      r `shouldSatisfy` (< 3)
    it "reading a literal of 400,000 digits takes at most about twice as long as 200,000" $ do
      let literal n = program "" ("X := 16#" <> T.replicate n "F" <> ";")
          work src = either (T.length . veKind) (length . show) (parseModule mastertoolXE "l.st" src)
      r <- doublingRatio literal T.length work 200000
      r `shouldSatisfy` (< 3)
    it "printing a chain of 40,000 terms takes at most about twice as long as 20,000" $ do
      let chain n = case parseModule mastertoolXE "c.st" (program "" ("X := " <> T.intercalate " + " (replicate n "1") <> ";")) of
            Left e -> error (show e)
            Right m -> m
      r <- doublingRatio chain (length . show) (T.length . prettyModule) 20000
      r `shouldSatisfy` (< 3)
  where
    isFine = \case
      Fine _ -> True
      InternalError _ -> False
    isSyntaxError = \case
      SyntaxErrorKind _ -> True
      _ -> False

tshow :: Show a => a -> Text
tshow = T.pack . show

takeBytes :: Int -> [Text] -> [Text]
takeBytes n (t : ts) | n > 0 = t : takeBytes (n - T.length t) ts
takeBytes _ _ = []

-- | How much longer the work takes on an input twice as large: the CPU time
-- on inputs of size 2n over that on size n, each the best of three runs on
-- freshly built inputs (sizes n, n+1, n+2, so nothing is shared between runs)
-- after a garbage collection. A burst of load on a shared machine then does
-- not decide a complexity test: linear work gives about 2, quadratic about 4.
doublingRatio :: (Int -> a) -> (a -> Int) -> (a -> Int) -> Int -> IO Double
doublingRatio build size work n = do
  t1 <- best n
  t2 <- best (2 * n)
  pure (t2 / max 1e-3 t1)
  where
    best m = minimum <$> mapM (\k -> once (m + k)) [0, 1, 2]
    once m = do
      x <- evaluate (build m)
      _ <- evaluate (size x)
      performGC
      cpuTime (work x)

cpuTime :: Int -> IO Double
cpuTime x = do
  a <- getCPUTime
  _ <- evaluate x
  b <- getCPUTime
  pure (fromIntegral (b - a) / 1e12)

stillRunning :: Int -> String -> IO Bool
stillRunning tries pid = do
  let stat = "/proc/" <> pid <> "/stat"
  exists <- doesPathExist stat
  running <-
    if not exists
      then pure False
      else do
        r <- try (BS.readFile stat) :: IO (Either IOException BS.ByteString)
        pure $ case r of
          Right s -> case words (drop 1 (dropWhile (/= ')') (BC.unpack s))) of
            (state : _) -> state /= "Z" && state /= "X"
            [] -> False
          Left _ -> False
  if running && tries > 0 then threadDelay 100000 >> stillRunning (tries - 1) pid else pure running

removeQuietly :: FilePath -> IO ()
removeQuietly p = do
  exists <- doesPathExist p
  if exists then removeFile p else pure ()

seedPrograms :: IO [Text]
seedPrograms = do
  files <- concat <$> mapM stFiles ["conformance", "test/examples"]
  mapM (fmap (either (const "") id . decodeSource) . BS.readFile) files
  where
    stFiles dir = do
      isDir <- doesDirectoryExist dir
      if not isDir
        then pure []
        else do
          entries <- map ((dir <> "/") <>) <$> listDirectory dir
          subs <- concat <$> mapM stFiles entries
          pure ([e | e <- entries, ".st" `T.isSuffixOf` T.pack e] ++ subs)
