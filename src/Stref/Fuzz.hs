-- | Fuzzing the whole pipeline: mutated programs (from seed programs such as
-- the conformance corpus) and random bytes go through decoding, parsing,
-- checking and a short run. Every input must end in a value, a verification
-- error or a runtime error; an exception, a hang or runaway allocation is an
-- internal error, and the harness shrinks the input that caused it.
--
-- Generation and classification are pure; only 'checkInput' (the guard that
-- catches exceptions, hangs and allocation) and the campaign loop are IO.
module Stref.Fuzz
  ( -- * Random numbers
    Rng
  , mkRng
  , inputRng
    -- * Inputs
  , generateInput
  , mutateText
  , hugeLiterals
  , deepNestings
    -- * Outcomes
  , Outcome (..)
  , evaluateInput
  , fuzzPolicies
  , fuzzStepBudget
    -- * The guard
  , Guard (..)
  , defaultGuard
  , Verdict (..)
  , checkInput
  , shrinkInput
  , FuzzReport (..)
  , fuzzCampaign
  ) where

import Control.Exception (SomeException, evaluate, try)
import Control.Monad.State.Strict (State, evalState, state)
import Data.Bits (shiftR, xor)
import qualified Data.ByteString as BS
import Data.ByteString (ByteString)
import Data.Int (Int64)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Encoding.Error as TE
import Data.Word (Word64, Word8)
import System.Mem (disableAllocationLimit, enableAllocationLimit, setAllocationCounter)
import System.Timeout (timeout)
import Stref.Checked (ModuleKind (..))
import Stref.Diagnostics (RuntimeError (..))
import Stref.Execution (CallResult (..), PlcState (..))
import Stref.IEC.Check (ProgramChoice (..))
import Stref.IEC.Engine (Call (..), RunResult (..), runProgram)
import Stref.IEC.Eval (Stop (..))
import Stref.Policy
import Stref.Run
import Stref.Source (decodeSource, renderEncodingError)
import Stref.Syntax.Parser (parseModule)
import Stref.Syntax.Pretty (prettyModule)
import Stref.Verification (VerificationError (..))

------------------------------------------------------------------------------
-- Random numbers: SplitMix64, so that an input is reproducible from the
-- campaign seed and its index alone.

newtype Rng = Rng Word64

mkRng :: Word64 -> Rng
mkRng = Rng

-- | The generator of input number @i@ of the campaign with seed @s@.
inputRng :: Word64 -> Int -> Rng
inputRng s i = Rng (mix (s `xor` mix (fromIntegral i + 0x51ED2701)))

mix :: Word64 -> Word64
mix z0 =
  let z1 = (z0 `xor` (z0 `shiftR` 30)) * 0xBF58476D1CE4E5B9
      z2 = (z1 `xor` (z1 `shiftR` 27)) * 0x94D049BB133111EB
   in z2 `xor` (z2 `shiftR` 31)

nextWord :: Rng -> (Word64, Rng)
nextWord (Rng s) = let s' = s + 0x9E3779B97F4A7C15 in (mix s', Rng s')

type Gen = State Rng

-- | A number in @[0, n)@ (0 when n <= 0).
below :: Int -> Gen Int
below n
  | n <= 0 = pure 0
  | otherwise = state (\g -> let (w, g') = nextWord g in (fromIntegral (w `mod` fromIntegral n), g'))

pick :: [a] -> Gen a
pick xs = (xs !!) <$> below (length xs) -- callers pass non-empty lists

chance :: Int -> Gen Bool
chance percent = (< percent) <$> below 100

------------------------------------------------------------------------------
-- Inputs

-- | Literals far outside every range: the pipeline must refuse or clamp them
-- without computing their value in full (no 10^999999999).
hugeLiterals :: [Text]
hugeLiterals =
  [ T.replicate 1000 "9"
  , "16#" <> T.replicate 500 "F"
  , "2#" <> T.replicate 2000 "1"
  , "8#" <> T.replicate 700 "7"
  , "1E999999999"
  , "1.0E999999999"
  , "1.5E-999999999"
  , "1.0E+2147483648"
  , "1.0E-2147483649"
  , "0.0E999999999"
  , T.replicate 400 "1" <> "." <> T.replicate 400 "1" <> "E-400"
  , "3.4028236E38"
  , "1E-46"
  , "2147483648"
  , "-2147483649"
  , "4294967296"
  , "16#1_0000_0000"
  , "1_000_000_000_000"
  , "65536"
  , "-32769"
  ]

-- | Constructs nested deeper than any program needs.
deepNestings :: Int -> [Text]
deepNestings n =
  [ T.replicate n "(" <> "1" <> T.replicate n ")"
  , T.intercalate " + " (replicate n "1")
  , T.intercalate " AND " (replicate n "TRUE")
  , T.replicate n "ABS(" <> "1" <> T.replicate n ")"
  , T.replicate n "NOT " <> "TRUE"
  , T.replicate n "- " <> "1"
  , T.replicate n "IF TRUE THEN " <> T.replicate n "END_IF; "
  , T.replicate n "WHILE FALSE DO " <> T.replicate n "END_WHILE; "
  , "IF FALSE THEN ;" <> T.replicate n " ELSIF FALSE THEN ;" <> " END_IF;"
  , T.replicate n "REPEAT " <> T.replicate n "UNTIL TRUE END_REPEAT; "
  ]

-- | Words and symbols of the language and a few operands, types, functions
-- and declarations, for insertions.
vocabulary :: [Text]
vocabulary =
  [ "IF", "THEN", "ELSE", "ELSIF", "END_IF", "CASE", "OF", "END_CASE", "FOR", "TO", "BY", "DO"
  , "END_FOR", "WHILE", "END_WHILE", "REPEAT", "UNTIL", "END_REPEAT", "EXIT", "RETURN"
  , "VAR", "VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "END_VAR", "CONSTANT", "AT", "ARRAY"
  , "FUNCTION", "END_FUNCTION", "PROGRAM", "END_PROGRAM", "TRUE", "FALSE", "AND", "OR", "XOR"
  , "NOT", "MOD", "BOOL", "BYTE", "WORD", "DWORD", "USINT", "INT", "DINT", "REAL"
  , ":=", ";", ":", ",", "(", ")", "[", "]", "..", "+", "-", "*", "/", "=", "<>", "<", ">"
  , "<=", ">=", "&", "(*", "*)", "#", "%", "."
  , "%M0000", "%M9999", "%M0000.15", "%M0000.16", "%F0001", "%I0002", "%TM0001[5]"
  , "%TM0001[-1]", "%TF0000[70000]", "%S0000", "%A0000", "%E0000", "%Q0000"
  , "EXPT", "SHL", "SHR", "ROL", "ROR", "ABS", "SQRT", "LN", "INT_TO_REAL", "REAL_TO_INT"
  , "REAL_TO_DINT", "DINT_TO_REAL", "ANY_TO_DINT", "ANY_TO_REAL", "BOOL_TO_INT"
  , "INTERNAL_OVERFLOW", "INPUT1", "OUTPUT1", "INPUT2", "OUTPUT3"
  , "0", "1", "-1", "32767", "-32768", "2147483647", "-2147483648", "16#FFFF", "16#FFFFFFFF"
  , "1.0", "0.0", "-0.0", "1.0E38", "3.4E38", "1.0E-45", "2#1010", "8#777"
  , "X", "Y", "I", "A", "F"
  , "ARRAY[0..2000000000] OF INT", "ARRAY[-2147483648..2147483647] OF DINT"
  , "ARRAY[5..0] OF INT", "ARRAY[0..1535] OF INT", "ARRAY[0..3072] OF BYTE"
  , "EXPT(2, 2147483647)", "EXPT(2.0, 1.0E38)", "SHL(1, 2147483647)", "ROL(16#FFFF, -1)"
  , "FOR I := 0 TO 32767 DO END_FOR;", "WHILE TRUE DO END_WHILE;"
  , "REPEAT UNTIL FALSE END_REPEAT;"
  ]

-- | Tokens for mutation: words (with numbers and based literals), runs of
-- white space, and single other characters.
tokenize :: Text -> [Text]
tokenize t = case T.uncons t of
  Nothing -> []
  Just (c, _)
    | wordy c -> let (a, b) = T.span wordy t in a : tokenize b
    | blank c -> let (a, b) = T.span blank t in a : tokenize b
    | otherwise -> T.take 1 t : tokenize (T.drop 1 t)
  where
    wordy x = x `elem` ['A' .. 'Z'] || x `elem` ['a' .. 'z'] || x `elem` ['0' .. '9'] || x `elem` ("_#." :: String)
    blank x = x `elem` (" \t\r\n" :: String)

-- | One to five token-level mutations of a program.
mutateText :: Text -> Gen Text
mutateText src = do
  k <- (+ 1) <$> below 5
  toks <- iterateM k mutateTokens (tokenize src)
  pure (T.concat toks)

iterateM :: Monad m => Int -> (a -> m a) -> a -> m a
iterateM 0 _ x = pure x
iterateM n f x = f x >>= iterateM (n - 1) f

mutateTokens :: [Text] -> Gen [Text]
mutateTokens toks = do
  let n = length toks
  i <- below n
  j <- below n
  op <- below 12
  case op of
    0 -> pure (deleteAt i toks)
    1 -> pure (take (i + 1) toks ++ drop i toks) -- duplicate token i
    2 -> pure (swap i j toks)
    3 -> do
      w <- pick vocabulary
      pure (insertAt i (" " <> w <> " ") toks)
    4 -> do
      w <- pick vocabulary
      pure (replaceAt i w toks)
    5 -> do
      h <- pick hugeLiterals
      -- replace a number if there is one, else insert
      let numbers = [x | (x, t) <- zip [0 ..] toks, startsWithDigit t]
      case numbers of
        [] -> pure (insertAt i (" " <> h <> " ") toks)
        _ -> do
          x <- pick numbers
          pure (replaceAt x h toks)
    6 -> pure (take i toks) -- truncation at a token
    7 -> do
      depth <- pick [10, 199, 200, 201, 1000, 10000]
      d <- pick (deepNestings depth)
      pure (insertAt i (" " <> d <> " ") toks)
    8 -> do
      -- a line deleted or duplicated
      let ls = T.lines (T.concat toks)
      l <- below (length ls)
      dup <- chance 50
      let ls' = if dup then take (l + 1) ls ++ drop l ls else deleteAt l ls
      pure (tokenize (T.unlines ls'))
    9 -> do
      -- a whole statement-like span swapped with another
      let a = min i j
          b = max i j
      pure (take a toks ++ reverse (take (b - a) (drop a toks)) ++ drop b toks)
    10 -> do
      -- a random ASCII character
      c <- below 128
      pure (insertAt i (T.singleton (toEnum c)) toks)
    _ -> do
      -- a random token from elsewhere in the program
      pure (if n == 0 then toks else insertAt i (toks !! j) toks)
  where
    startsWithDigit t = case T.uncons t of
      Just (c, _) -> c >= '0' && c <= '9'
      Nothing -> False

deleteAt :: Int -> [a] -> [a]
deleteAt i xs = take i xs ++ drop (i + 1) xs

insertAt :: Int -> a -> [a] -> [a]
insertAt i x xs = take i xs ++ [x] ++ drop i xs

replaceAt :: Int -> a -> [a] -> [a]
replaceAt i x xs = take i xs ++ [x] ++ drop (i + 1) xs

swap :: Int -> Int -> [a] -> [a]
swap i j xs
  | i == j || i >= length xs || j >= length xs = xs
  | otherwise = [pickAt k x | (k, x) <- zip [0 ..] xs]
  where
    pickAt k x
      | k == i = xs !! j
      | k == j = xs !! i
      | otherwise = x

-- | Byte-level damage: random bytes, invalid UTF-8, truncation in the middle
-- of a character.
mutateBytes :: ByteString -> Gen ByteString
mutateBytes bs = do
  op <- below 4
  i <- below (BS.length bs + 1)
  case op of
    0 -> do
      k <- (+ 1) <$> below 8
      junk <- randomBytes k
      pure (BS.take i bs <> junk <> BS.drop i bs)
    1 -> do
      bad <- pick invalidUtf8
      pure (BS.take i bs <> bad <> BS.drop i bs)
    2 -> pure (BS.take i bs)
    _ -> do
      b <- fromIntegral <$> below 256
      pure (if BS.null bs then bs else BS.take i bs <> BS.singleton b <> BS.drop (i + 1) bs)

invalidUtf8 :: [ByteString]
invalidUtf8 =
  map
    BS.pack
    [ [0xFF]
    , [0xC0, 0xAF] -- overlong '/'
    , [0xED, 0xA0, 0x80] -- a surrogate
    , [0xF4, 0x90, 0x80, 0x80] -- above U+10FFFF
    , [0xE2, 0x82] -- truncated
    , [0x80]
    , [0xE9] -- Latin-1 e acute
    , [0xEF, 0xBB, 0xBF] -- a byte order mark (valid, but not at the start)
    , [0xC3, 0xA7] -- a valid c cedilla
    , [0x00]
    ]

randomBytes :: Int -> Gen ByteString
randomBytes k = BS.pack <$> mapM (const (fromIntegral <$> below 256 :: Gen Word8)) [1 .. k]

-- | One input from a list of seed programs: mostly mutated seeds, sometimes
-- damaged bytes, a deep construct in a small program, or random bytes.
generateInput :: [Text] -> Rng -> ByteString
generateInput seeds = evalState gen
  where
    gen = do
      r <- below 100
      case () of
        _
          | r < 8 || null seeds -> do
              k <- below 300
              randomBytes k
          | r < 14 -> do
              k <- below 60
              toks <- mapM (const (pick vocabulary)) [1 .. k]
              pure (TE.encodeUtf8 (T.unwords toks))
          | r < 22 -> do
              depth <- pick [199, 200, 201, 2000, 10000]
              d <- pick (deepNestings depth)
              isStmt <- chance 50
              pure . TE.encodeUtf8 $
                if isStmt
                  then "PROGRAM P\nVAR X : DINT; B : BOOL; END_VAR\n" <> d <> "\nEND_PROGRAM\n"
                  else "PROGRAM P\nVAR X : DINT; B : BOOL; END_VAR\nX := " <> d <> ";\nEND_PROGRAM\n"
          | otherwise -> do
              s <- pick seeds
              t <- mutateText s
              damage <- chance 15
              let b = TE.encodeUtf8 t
              if damage then mutateBytes b else pure b

------------------------------------------------------------------------------
-- Outcomes

-- | How an input ended, when it ended properly.
data Outcome
  = InvalidEncoding
  | SyntaxErrorKind Text
  | RejectedKinds [Text]
  | Ran [Maybe Int] -- ^ the runtime error code of each call, if any
  deriving (Eq, Show)

-- | A small step budget keeps every run short.
fuzzStepBudget :: Int
fuzzStepBudget = 20000

fuzzPolicies :: Policies
fuzzPolicies = mastertoolXE {pStepBudget = fuzzStepBudget}

-- | The IEC core's policies for fuzzing: the tecomat and nexto presets (the
-- nexto grammar: CODESYS extensions, pragmas, OOP), a small budget.
iecFuzzPolicies :: [Policies]
iecFuzzPolicies = [p {pStepBudget = fuzzStepBudget} | p <- [tecomat, nexto]]

-- | Decode, parse, print, check and run (two calls) one input, a short one
-- also as an @stref eval@ snippet; the text is
-- everything the user could see, so forcing it forces the whole pipeline.
-- Bytes that are not UTF-8 are also run leniently decoded, so that odd
-- characters reach the lexer.
evaluateInput :: ByteString -> (Outcome, Text)
evaluateInput bytes = case decodeSource bytes of
  Left bad ->
    let (_, seen) = pipeline (TE.decodeUtf8With TE.lenientDecode bytes)
     in (InvalidEncoding, renderEncodingError file bad <> seen)
  Right src -> let (o, seen) = pipeline src in (o, seen <> snippet src <> iecPipeline src)
  where
    file = "fuzz.st"
    pipeline src =
      let kind = if any (`T.isInfixOf` T.toUpper src) ["VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT"] then FunctionModule else ProcedureModule
          printed = either (const "") prettyModule (parseModule fuzzPolicies file src)
          setup = defaultRunSetup {rsPolicies = fuzzPolicies, rsKind = kind}
       in case runSource setup file src [defaultCallSpec, defaultCallSpec] of
            Left f ->
              let outcome = case f of
                    SyntaxError e -> SyntaxErrorKind (veKind e)
                    Rejected es -> RejectedKinds (map veKind es)
                    BadSetting _ -> RejectedKinds ["bad-setting"]
               in (outcome, printed <> renderRunFailure file src f)
            Right ro ->
              let codes = [fmap (\(RuntimeError c _ _) -> c) (crError r) | r <- roResults ro]
               in (Ran codes, printed <> T.pack (show (roResults ro, psMemory (roFinal ro))))
    -- every input also goes through the IEC core under each IEC dialect:
    -- parse, check, two cycles
    iecPipeline src = T.concat [iecRun pol src | pol <- iecFuzzPolicies]
    iecRun pol src = case runProgram pol file src ProgramsOfConfiguration 10 [] [Scan [], Scan []] of
      Left e -> veKind e <> veMessage e
      Right (Left t) -> t
      Right (Right r) -> T.pack (show (rrMachine r, fmap (\(k, StopFault p f) -> (k, p, f)) (rrError r), rrCycles r))
    -- short inputs also go through @stref eval@'s wrapping
    snippet src
      | T.length src > 1000 = ""
      | otherwise = case evalSnippet fuzzPolicies src of
          Left (wrapped, f) -> renderRunFailure "<eval>" wrapped f
          Right sr -> T.pack (show (srResult sr))

------------------------------------------------------------------------------
-- The guard

-- | Limits of the harness only: far above what a proper input needs, so that
-- hitting one means a hang or runaway allocation.
data Guard = Guard
  { gTimeMicros :: Int
  , gAllocBytes :: Int64
  }

defaultGuard :: Guard
defaultGuard = Guard 30000000 8000000000

data Verdict
  = Fine Outcome
  | InternalError Text -- ^ an exception, a hang or runaway allocation
  deriving (Eq, Show)

-- | Evaluate one input completely under the guard.
checkInput :: Guard -> ByteString -> IO Verdict
checkInput g bytes = do
  r <- try $ do
    setAllocationCounter (gAllocBytes g)
    enableAllocationLimit
    res <- timeout (gTimeMicros g) $ do
      let (outcome, seen) = evaluateInput bytes
      _ <- evaluate (T.length seen)
      evaluate (length (show outcome)) >> pure outcome
    disableAllocationLimit
    pure res
  disableAllocationLimit
  pure $ case r of
    Left (e :: SomeException) -> InternalError ("exception: " <> T.pack (show e))
    Right Nothing -> InternalError ("no result within " <> T.pack (show (gTimeMicros g `div` 1000000)) <> " s (a hang)")
    Right (Just o) -> Fine o

-- | Make a failing input smaller while it keeps failing: drop halves,
-- lines, tokens, then single bytes, each as long as one removal still fails.
-- At most the given number of candidates are tried (a hang costs a guard's
-- time per try).
shrinkInput :: Int -> (ByteString -> IO Bool) -> ByteString -> IO ByteString
shrinkInput budget0 stillFails = go budget0
  where
    go budget bs = do
      (smaller, left) <- firstFailing budget (candidates bs)
      maybe (pure bs) (go left) smaller
    firstFailing budget [] = pure (Nothing, budget)
    firstFailing budget (c : cs)
      | budget <= 0 = pure (Nothing, 0)
      | otherwise = do
          f <- stillFails c
          if f then pure (Just c, budget - 1) else firstFailing (budget - 1) cs
    candidates bs =
      let ls = BS.split 10 bs
          lineCuts = [BS.intercalate "\n" (deleteAt i ls) | length ls > 1, i <- [0 .. length ls - 1]]
          toks = tokenizeBytes bs
          tokCuts = [BS.concat (deleteAt i toks) | length toks > 1, length toks <= 400, i <- [0 .. length toks - 1]]
          halves = [h | BS.length bs > 1, h <- [BS.take (BS.length bs `div` 2) bs, BS.drop (BS.length bs `div` 2) bs]]
          byteCuts = [BS.take i bs <> BS.drop (i + 1) bs | BS.length bs <= 200, i <- [0 .. BS.length bs - 1]]
       in halves ++ lineCuts ++ tokCuts ++ byteCuts
    tokenizeBytes bs = case decodeSource bs of
      Right t -> map TE.encodeUtf8 (tokenize t)
      Left _ -> map BS.singleton (BS.unpack bs)

-- | The result of a campaign.
data FuzzReport = FuzzReport
  { frRun :: Int -- ^ inputs evaluated
  , frFailure :: Maybe (Int, Text, ByteString, ByteString)
  -- ^ index, what went wrong, the input, and the shrunk input
  }

-- | Evaluate inputs @from .. from+count-1@ of the campaign with the given
-- seed, reporting progress after every input; stop at the first internal
-- error and shrink it.
fuzzCampaign :: Guard -> [Text] -> Word64 -> Int -> Int -> (Int -> Verdict -> IO ()) -> IO FuzzReport
fuzzCampaign g seeds seed from count progress = loop from
  where
    end = from + count
    loop i
      | i >= end = pure (FuzzReport (i - from) Nothing)
      | otherwise = do
          let input = generateInput seeds (inputRng seed i)
          v0 <- checkInput g input
          -- a hang is confirmed with a three times longer guard, so that a
          -- loaded machine does not count as one
          v <- case v0 of
            InternalError why | "no result" `T.isPrefixOf` why -> checkInput g {gTimeMicros = 3 * gTimeMicros g} input
            _ -> pure v0
          progress i v
          case v of
            InternalError why -> do
              let failsSame b = do
                    v' <- checkInput g b
                    pure (isInternal v')
              small <- shrinkInput 300 failsSame input
              pure (FuzzReport (i - from + 1) (Just (i, why, input, small)))
            Fine _ -> loop (i + 1)
    isInternal = \case
      InternalError _ -> True
      Fine _ -> False
