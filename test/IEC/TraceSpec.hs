-- | The trace of IEC runs (docs/trace.md): the lines, values and rule ids a
-- known program's trace must show, worked out by hand from the rules
-- named; and that tracing changes no result (the whole corpus, traced and
-- not).
module IEC.TraceSpec (spec) where

import qualified Data.Aeson as A
import qualified Data.ByteString.Lazy as BL
import Data.Maybe (isJust)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import Stref.Conformance.Case (Case (..), effectiveExpect)
import Stref.Conformance.Corpus
import Stref.Conformance.Runner (buildRequest, casePolicies, defaultRunOptions)
import Stref.IEC.Check (ProgramChoice (..))
import Stref.Engine (referenceEngine, referenceTrace)
import Stref.IEC.Engine
import Stref.IEC.Eval (traceOf)
import Stref.Policy
import Stref.Trace
import Test.Hspec

-- | The trace of a program over some cycles, as text lines.
traced :: Bool -> Policies -> Text -> Int -> [Text]
traced every pol src n = case runProgramTraced (Just every) pol "trace.st" src ProgramsOfConfiguration 10 [] (replicate n (Scan [])) of
  Right (Right r) -> renderText pol line (items (traceOf (rrMachine r)))
  other -> error ("the program did not run: " <> show (fmap (fmap rrCycles) other))
  where
    line l = case drop (l - 1) (T.lines src) of
      x : _ -> x
      [] -> ""

-- | Lines 1..: the overflow of line 9 in the second iteration.
accumulate :: Text
accumulate =
  T.unlines
    [ "PROGRAM MAIN"
    , "VAR"
    , "  acc : DINT := 2147483000;"
    , "  v : ARRAY[1..3] OF DINT := [100, 300, 500];"
    , "  i : INT;"
    , "END_VAR"
    , "FOR i := 1 TO 3 DO"
    , "  (* the second iteration leaves DINT *)"
    , "  acc := acc + v[i] * 3;"
    , "END_FOR;"
    , "END_PROGRAM"
    ]

counting :: Text
counting = "PROGRAM MAIN\nVAR cnt : INT; END_VAR\nWHILE cnt < 10 DO\n  cnt := cnt + 1;\nEND_WHILE;\nEND_PROGRAM\n"

outOfBounds :: Text
outOfBounds = "PROGRAM MAIN\nVAR arr : ARRAY[0..2] OF INT; ix : INT := 5; END_VAR\narr[ix] := 1;\nEND_PROGRAM\n"

has :: [Text] -> Text -> Bool
has ls x = any (x `T.isInfixOf`) ls

spec :: Spec
spec = describe "IEC.Trace" $ do
  describe "a known program's text trace" $ do
    let sat = traced False tecomat {pOverflow = Saturate} accumulate 1
    it "shows the statement of line 9 with the values it read and wrote" $ do
      sat `shouldSatisfy` (`has` "9 |   acc := acc + v[i] * 3;")
      -- 2147483300 + 300 * 3 = 2147484200 > 2^31 - 1
      sat `shouldSatisfy` (`has` "acc = 2147483300, i = 2, v[2] = 300; -> acc := 2147483647")
    it "cites the overflow rule of the tecomat catalogue with the alternative in force (TC-OP-20)" $
      sat `shouldSatisfy` (`has` "rule TC-OP-20: 2147483300 + 900 = 2147484200 lies outside DINT: the result is 2147483647 (overflow=saturate)")
    it "under overflow=wrap the same rule gives the wrapped value" $
      traced False tecomat {pOverflow = Wrap} accumulate 1 `shouldSatisfy` (`has` "the result is -2147483096 (overflow=wrap)")
    it "under nexto cites the nexto catalogue's ids (NX-OP-32)" $
      traced False nexto accumulate 1 `shouldSatisfy` (`has` "rule NX-OP-32, NX-ERR-24: ")
    it "shows the FOR bounds and the for-bounds decision (TC-STMT-26)" $ do
      sat `shouldSatisfy` (`has` "i from 1 to 3 by 1")
      sat `shouldSatisfy` (`has` "rule TC-STMT-26, TC-STMT-27: the final value and the step are evaluated again at every test (for-bounds=every-iteration)")
      traced False tecomat {pForBounds = ForOnce} accumulate 1 `shouldSatisfy` (`has` "evaluated once, before the first test (for-bounds=once)")
    it "marks each cycle" $
      filter (== "cycle 2") (traced False tecomat accumulate 2) `shouldBe` ["cycle 2"]
  describe "REAL and TIME arithmetic" $ do
    -- 3.0E38 * 10 = 3E39 > 3.4028235E38, the largest REAL; T#24d + T#24d = 4147200000 ms >
    -- 2^31 - 1 (signed, TC-TYPE-19), < 2^32 - 1 (unsigned, NX-TYPE-30)
    let realTime = "PROGRAM MAIN\nVAR big : REAL := 3.0E38; zz : REAL; tt : TIME := T#24d; END_VAR\nbig := big * 10.0;\nzz := 1.0 / 0.0;\ntt := tt + T#24d;\nEND_PROGRAM\n"
    it "an infinite REAL result of finite operands is the real-overflow decision (TC-OP-26)" $ do
      traced False tecomat {pRealOverflow = RealOverflowIeee} realTime 1 `shouldSatisfy` (`has` "rule TC-OP-26: 3.0e38 * 10.0 leaves the range of REAL: the result is Infinity (real-overflow=ieee)")
      traced False tecomat {pRealOverflow = RealOverflowSaturate} realTime 1 `shouldSatisfy` (`has` "the result is 3.4028235e38 (real-overflow=saturate)")
    it "a REAL division by zero is the real-div-zero decision (TC-OP-22)" $
      traced False tecomat {pRealDivZero = RealDivZeroIeee} realTime 1 `shouldSatisfy` (`has` "rule TC-OP-22, TC-OP-26: 1.0 / 0.0: division by zero gives Infinity (real-div-zero=ieee)")
    it "a duration outside TIME's range is the overflow decision over the time range (TC-OP-49, TC-TYPE-19)" $ do
      traced False tecomat {pOverflow = Saturate} realTime 1 `shouldSatisfy` (`has` "T#24d + T#24d lies outside TIME (time-range=signed): the result is T#24d20h31m23s647ms (overflow=saturate)")
      traced False tecomat {pTimeRange = TimeUnsigned} realTime 1 `shouldNotSatisfy` (`has` "T#24d + T#24d lies outside")
    -- T#20d * 3 = 5184000000 ms > 2^31 - 1; 60 years of days > 2^31 - 1 ms
    let scaled = "PROGRAM MAIN\nVAR tt : TIME := T#20d; span : TIME; nought : DINT := 0; quotient : TIME; gap : TIME; later : DATE := D#2030-01-01; earlier : DATE := D#1970-01-01; END_VAR\nspan := tt * 3;\nquotient := tt / nought;\ngap := later - earlier;\nEND_PROGRAM\n"
    it "a duration scaled or a difference of dates outside TIME's range is the overflow decision; a duration divided by 0 is div-zero (TC-OP-53, TC-OP-58, TC-OP-59)" $ do
      let t = traced False tecomat {pOverflow = Saturate, pDivZero = DivZeroZero} scaled 1
      t `shouldSatisfy` (`has` "rule TC-OP-58, TC-TYPE-19: T#20d * 3 lies outside TIME (time-range=signed): the result is T#24d20h31m23s647ms (overflow=saturate)")
      t `shouldSatisfy` (`has` "rule TC-OP-22, TC-OP-59: T#20d / 0: division by zero gives T#0ms (div-zero=zero)")
      t `shouldSatisfy` (`has` "rule TC-OP-53, TC-TYPE-19: D#2030-01-01 - D#1970-01-01 lies outside TIME")
      traced False tecomat scaled 1 `shouldSatisfy` (`has` "T#20d / 0: division by zero is a runtime error (div-zero=error)")
  describe "long loops" $ do
    it "show their first 3 iterations, then a count" $ do
      let t = traced False tecomat counting 1
      length (filter ("cnt := cnt + 1;" `T.isInfixOf`) t) `shouldBe` 3
      t `shouldSatisfy` (`has` "... 7 more iterations not shown")
      t `shouldSatisfy` (`has` "loop ends after 10 iterations")
    it "show every iteration with --trace-all" $ do
      let t = traced True tecomat counting 1
      length (filter ("cnt := cnt + 1;" `T.isInfixOf`) t) `shouldBe` 10
      t `shouldNotSatisfy` (`has` "not shown")
  describe "runtime errors" $ do
    it "show the rule that makes them one (TC-ERR-3)" $
      traced False tecomat outOfBounds 1 `shouldSatisfy` (`has` "runtime error: the index 5 lies outside the bounds 0..2 (TC-ERR-3)")
    it "under index-out-of-range=clamp the clamp is a rule decision instead" $
      traced False tecomat {pIndexOutOfRange = IndexClamp} outOfBounds 1 `shouldSatisfy` (`has` "the index 5 lies outside 0..2: clamped to 2 (index-out-of-range=clamp)")
  describe "the JSON event stream" $ do
    let Right (Right r) = runProgramTraced (Just False) tecomat {pOverflow = Saturate} "trace.st" accumulate ProgramsOfConfiguration 10 [] [Scan []]
        jsonLines = renderJsonLines tecomat {pOverflow = Saturate} (items (traceOf (rrMachine r)))
        decoded = map (A.decode . BL.fromStrict . TE.encodeUtf8) jsonLines :: [Maybe A.Value]
    it "is one JSON object per line" $
      decoded `shouldSatisfy` all isJust
    it "gives a statement its reads, writes and rules with policy and alternative" $
      jsonLines `shouldSatisfy` (`has` "{\"alternative\":\"saturate\",\"policy\":\"overflow\",\"rules\":[\"TC-OP-20\"]")
  describe "tracing changes no result" $
    it "every corpus case, of every dialect, gives the same answer traced (conformance --explain) and not" $ do
      corpus <- loadCorpus ["conformance"]
      let cases = [c | Loaded c <- corpusEntries corpus]
          differing =
            [ caseId c
            | c <- cases
            , Right pol <- [casePolicies defaultRunOptions c]
            , let rq = buildRequest pol c (effectiveExpect pol c)
            , fmap (\(_, a, _) -> a) (referenceTrace [] rq) /= Right (referenceEngine [] rq)
            ]
      length cases `shouldSatisfy` (> 2000)
      differing `shouldBe` []
