module ConformanceCaseSpec (spec) where

import Conformance.Paths
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Conformance.Case
import Stref.Conformance.Corpus
import Stref.Conformance.Rules
import Stref.Operands
import Stref.Policy (mastertoolXE, setPolicy)
import Stref.Values (realBits)
import System.FilePath ((</>))
import Test.Hspec

loaded :: Text -> IO Case
loaded cid = do
  corpus <- loadCorpus [fixtureCorpus]
  case [c | Loaded c <- corpusEntries corpus, caseId c == cid] of
    [c] -> pure c
    _ -> fail ("fixture " <> T.unpack cid <> " did not load: " <> show [e | Invalid _ _ e <- corpusEntries corpus])

-- | The error of a malformed fixture.
invalid :: FilePath -> IO Text
invalid name = do
  corpus <- loadCorpus [malformedCorpus </> "mastertool-xe" </> "bad" </> name]
  case corpusEntries corpus of
    [Invalid _ _ e] -> pure e
    other -> fail ("expected one invalid entry, got " <> show (map entryId other))

m :: Int -> Operand
m = OpSimple KM

spec :: Spec
spec = describe "Conformance case files" $ do
  expectIfSpec
  it "loads a case named twice (a directory and a file in it) once" $ do
    whole <- loadCorpus [fixtureCorpus]
    let file = fixtureCorpus </> "mastertool-xe" </> "arith" </> "int-add-saturates.st"
    twice <- loadCorpus [fixtureCorpus, file, file]
    map entryId (corpusEntries twice) `shouldBe` map entryId (corpusEntries whole)
  it "loads the same entries with several workers" $ do
    one <- loadCorpus [fixtureCorpus]
    three <- loadCorpusWith 3 [fixtureCorpus]
    map entryId (corpusEntries three) `shouldBe` map entryId (corpusEntries one)
    [c | Loaded c <- corpusEntries three] `shouldBe` [c | Loaded c <- corpusEntries one]
  it "loads the contract's example case with its id, area, metadata and defaults" $ do
    c <- loaded "mastertool-xe/arith/int-add-saturates"
    caseDialect c `shouldBe` "mastertool-xe"
    caseArea c `shouldBe` "arith"
    caseRules c `shouldBe` ["MT-OP-6", "MT-OP-7"]
    caseFeatures c `shouldBe` ["saturation", "internal-overflow"]
    caseStatus c `shouldBe` Normative
    psInit (casePlc c) `shouldBe` [(m 10, EInt 15000), (m 11, EInt 25000)]
    psConfig (casePlc c) `shouldBe` defaultPlcConfig
    caseCalls c `shouldBe` [CallSetup (True, True, True) []]
    let ex = caseExpect c
    exOperands ex `shouldBe` M.fromList [(m 12, EInt 32767), (OpBit KM 13 0, EBool True)]
    exOutputs ex `shouldBe` M.fromList [(1, True)]
    exError ex `shouldBe` Just ErrNone
    expectedVerdict ex `shouldBe` ExpOk

  it "chooses expect-if entries by the engine's policies" $ do
    c <- loaded "mastertool-xe/arith/int-add-saturates"
    wrap <- either (fail . T.unpack) pure (setPolicy "overflow" "wrap" mastertoolXE)
    M.lookup (m 12) (exOperands (effectiveExpect mastertoolXE c)) `shouldBe` Just (EInt 32767)
    -- 15000 + 25000 = 40000 = 40000 - 65536 = -25536 in 16 bits
    M.lookup (m 12) (exOperands (effectiveExpect wrap c)) `shouldBe` Just (EInt (-25536))
    -- the entry overrides only what it states
    M.lookup (OpBit KM 13 0) (exOperands (effectiveExpect wrap c)) `shouldBe` Just (EBool True)

  it "reads a list of calls with inputs and set" $ do
    c <- loaded "mastertool-xe/calls/three-calls"
    caseCalls c
      `shouldBe` [ CallSetup (True, False, True) [(m 100, EInt 1)]
                 , CallSetup (True, True, True) [(m 100, EInt 2)]
                 , CallSetup (False, False, False) []
                 ]

  it "infers the verdict runtime-error from an error code" $ do
    c <- loaded "mastertool-xe/calls/div-zero"
    exError (caseExpect c) `shouldBe` Just (ErrCode 2020 (Just 12) Nothing)
    expectedVerdict (caseExpect c) `shouldBe` ExpRuntimeError

  it "rounds a decimal once, straight to binary32" $ do
    -- the decimal is exactly 1 + 2^-24 + 2^-60: just above the midpoint
    -- between 1.0 and 1 + 2^-23, so it rounds up to 0x3F800001. Through
    -- binary64 it would first become 1 + 2^-24, a tie, and round to 1.0.
    c <- loaded "mastertool-xe/arith/real-rounding"
    case psInit (casePlc c) of
      [(OpSimple KF 1, EReal f)] -> realBits f `shouldBe` 0x3F800001
      other -> expectationFailure ("unexpected init " <> show other)
    M.lookup (OpSimple KF 1) (exOperands (caseExpect c)) `shouldBe` Just (EBits 0x3F800001)

  it "reads 0.1 as the binary32 nearest to it" $ do
    c <- loaded "mastertool-xe/arith/real-sum"
    -- 0.1 = 0x3DCCCCCD and 0.2 = 0x3E4CCCCD (nearest binary32, by hand:
    -- 0.1 * 2^27 = 13421772.8 rounds to 13421773 = 0xCCCCCD)
    [(op, realBits f) | (op, EReal f) <- psInit (casePlc c)] `shouldBe` [(OpSimple KF 1, 0x3DCCCCCD), (OpSimple KF 2, 0x3E4CCCCD)]

  describe "malformed cases give file:line: message" $ do
    let file n = T.pack (malformedCorpus </> "mastertool-xe" </> "bad" </> n)
    it "bad YAML: the line where the parser found the problem" $ do
      -- the flow sequence opened on line 4 is found unclosed on line 5
      e <- invalid "bad-yaml.st"
      e `shouldSatisfy` T.isPrefixOf (file "bad-yaml.st" <> ":5: invalid YAML in the metadata")
    it "an expect-if entry whose runtime-error verdict would inherit error: none" $ do
      e <- invalid "runtime-error-inherits-none.st"
      e `shouldSatisfy` T.isInfixOf "expect-if[0]: verdict runtime-error, but the entry states no error"
    it "an unknown key" $ do
      e <- invalid "unknown-key.st"
      e `shouldSatisfy` T.isPrefixOf (file "unknown-key.st" <> ":6: expect.outptus: unknown key 'outptus'")
    it "an operand outside the declared layout" $ do
      e <- invalid "unknown-operand.st"
      e `shouldBe` file "unknown-operand.st" <> ":9: expect.operands.%M0500: operand %M0500 does not exist in this case's PLC layout (see plc.declare)"
    it "a rule id that RULES does not list" $ do
      e <- invalid "unknown-rule.st"
      e `shouldBe` file "unknown-rule.st" <> ":3: rules: rule MT-NOPE-1 is not in the dialect's RULES index"
    it "a file without the metadata comment" $ do
      e <- invalid "no-metadata.st"
      e `shouldSatisfy` T.isPrefixOf (file "no-metadata.st" <> ":1: the first comment of a case must be its metadata")
    it "a value too large for its operand" $ do
      e <- invalid "int-too-big.st"
      e `shouldBe` file "int-too-big.st" <> ":6: plc.init.%M0010: 70000 does not fit the 16 bits of %M0010"
    it "an expect-if choice the policy does not have" $ do
      e <- invalid "bad-policy.st"
      e `shouldSatisfy` T.isPrefixOf (file "bad-policy.st" <> ":6: expect-if[0].when.overflow: policy overflow has no alternative 'explode'")

  describe "the metadata comment" $ do
    it "starts at the line of (*--- and ends at ---*)" $
      extractMetadata "\n(*---\nrules: [X]\n---*)\nPROGRAM P\nEND_PROGRAM\n" `shouldBe` Right (2, "\nrules: [X]\n")
    it "must be closed" $
      either (Just . fst) (const Nothing) (extractMetadata "(*---\nrules: [X]\n") `shouldBe` Just 1

  describe "the RULES index" $ do
    it "reads rules, untestable rules, comments and blank lines" $
      parseRules "RULES" "# head\n\nMT-A-1 | first\nMT-A-2 | second | untestable: needs hardware\n"
        `shouldBe` Right [Rule "MT-A-1" "first" Nothing 3, Rule "MT-A-2" "second" (Just "needs hardware") 4]
    it "reports malformed and duplicate lines with their line numbers" $
      parseRules "RULES" "MT-A-1 | first\nno separator\nMT-A-1 | again\nMT-A-3 | x | maybe\n"
        `shouldBe` Left
          [ "RULES:2: expected 'ID | title' or 'ID | title | untestable: reason'"
          , "RULES:4: the third field must read 'untestable: <reason>'"
          , "RULES:3: rule MT-A-1 is listed twice"
          ]

-- | A case parsed from text, for the expect-if rules.
policyCase :: Text -> Either Text Case
policyCase meta =
  parseCase "t.st" (CaseOrigin "mastertool-xe/t/t" "mastertool-xe" "t") (const True) ("(*---\n" <> meta <> "---*)\nPROGRAM P\nEND_PROGRAM\n")

expectIfSpec :: Spec
expectIfSpec = describe "expect-if entries" $ do
  let under k v = either (error . T.unpack) id (setPolicy k v mastertoolXE)
  it "an entry's error code turns the verdict into runtime-error" $ do
    c <- either (fail . T.unpack) pure . policyCase $
      "description: d\nrules: [R]\nexpect:\n  operands: {\"%M0012\": 32767}\n  error: none\nexpect-if:\n  - when: {overflow: trap}\n    error: {code: 9001}\n"
    let trap = effectiveExpect (under "overflow" "trap") c
    expectedVerdict trap `shouldBe` ExpRuntimeError
    exError trap `shouldBe` Just (ErrCode 9001 Nothing Nothing)
    expectedVerdict (effectiveExpect mastertoolXE c) `shouldBe` ExpOk
  it "an entry's ok drops the error code of expect" $ do
    c <- either (fail . T.unpack) pure . policyCase $
      "description: d\nrules: [R]\nexpect:\n  error: {code: 2020}\nexpect-if:\n  - when: {div-zero: zero}\n    verdict: ok\n    operands: {\"%M0012\": 0}\n"
    let zero = effectiveExpect (under "div-zero" "zero") c
    (expectedVerdict zero, exError zero) `shouldBe` (ExpOk, Nothing)
  it "an entry's rejection drops the error of expect" $ do
    c <- either (fail . T.unpack) pure . policyCase $
      "description: d\nrules: [R]\nexpect:\n  error: none\nexpect-if:\n  - when: {elsif-keyword: ELSIF}\n    reject: {kind: syntax-error}\n"
    let strict = effectiveExpect (under "elsif-keyword" "ELSIF") c
    (expectedVerdict strict, exError strict, exReject strict) `shouldBe` (ExpRejected, Nothing, Just (ExpReject Nothing (Just "syntax-error")))
