-- | The MasterTool XE trace (#24): the events of known programs (lines,
-- values, rule ids and policies), and a traced run that ends exactly as
-- the untraced one, on the MasterTool XE corpus.
module TraceMasterToolSpec (spec) where

import Data.Maybe (mapMaybe)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Checked (ModuleKind (..))
import qualified Stref.Conformance.Case as C
import Stref.Conformance.Corpus
import Stref.Operands (Operand)
import Stref.Policy
import Stref.Run
import Stref.Trace
import Test.Hspec

-- | The events of @n@ calls of a P module, every iteration kept or not.
traceOf :: Policies -> Bool -> Int -> Text -> [Event]
traceOf pol everyIteration n src = case compileSource pol ProcedureModule "t.st" src of
  Left failure -> error (show failure)
  Right cm -> case runModuleTraced everyIteration defaultRunSetup {rsPolicies = pol} cm (replicate n defaultCallSpec) of
    Left failure -> error (show failure)
    Right (_, events) -> events

-- | The text trace, with the source lines.
textOf :: Policies -> Text -> [Event] -> Text
textOf pol src = T.unlines . renderText pol source . items
  where
    source l = case drop (l - 1) (T.lines src) of
      s : _ | l >= 1 -> s
      _ -> ""

-- | The decisions told at a line.
rulesAt :: Int -> [Event] -> [Decision]
rulesAt l evs = [d | Rule l' d <- evs, l' == l]

with :: [(Text, Text)] -> Policies
with = foldl (\p (k, v) -> either (error . T.unpack) id (setPolicy k v p)) mastertoolXE

program :: [Text] -> Text
program = T.unlines

overflowProgram :: Text
overflowProgram =
  program
    [ "VAR" -- 1
    , "  ACC : DINT;" -- 2
    , "  V : ARRAY[1..3] OF DINT;" -- 3
    , "END_VAR" -- 4
    , "PROGRAM P" -- 5
    , "ACC := 2147483000;" -- 6
    , "V[2] := 900;" -- 7
    , "ACC := ACC + V[2];" -- 8
    , "END_PROGRAM" -- 9
    ]

forProgram :: Text
forProgram =
  program
    [ "VAR I : INT; S : INT; END_VAR" -- 1
    , "PROGRAM P" -- 2
    , "FOR I := 1 TO 10 DO" -- 3
    , "  S := S + I;" -- 4
    , "END_FOR;" -- 5
    , "END_PROGRAM" -- 6
    ]

spec :: Spec
spec = do
  describe "the MasterTool XE trace of a known program" $ do
    it "shows an overflow saturating under the preset: MT-OP-6 with overflow=saturate, the flag (MT-OP-7) and the value written" $ do
      let evs = traceOf mastertoolXE False 1 overflowProgram
      evs `shouldContain` [Wrote 8 "ACC" "2147483647"]
      [Read 8 "ACC" "2147483000", Read 8 "V[2]" "900"] `shouldSatisfy` all (`elem` evs)
      [(dRules d, dPolicy d) | d <- rulesAt 8 evs, "2147483000 + 900 = 2147483647: DINT saturates" `T.isInfixOf` dSays d]
        `shouldBe` [(["MT-OP-6"], Just "overflow")]
      map dRules (rulesAt 8 evs) `shouldContain` [["MT-OP-7"]]
      let text = textOf mastertoolXE overflowProgram evs
      text `shouldSatisfy` T.isInfixOf "rule MT-OP-6: 2147483000 + 900 = 2147483647: DINT saturates (overflow=saturate)"
      text `shouldSatisfy` T.isInfixOf "ACC := ACC + V[2];"
      text `shouldSatisfy` T.isInfixOf "-> ACC := 2147483647"
    it "shows the alternative in force: overflow=wrap wraps around" $ do
      let pol = with [("overflow", "wrap")]
          evs = traceOf pol False 1 overflowProgram
      evs `shouldContain` [Wrote 8 "ACC" "-2147483396"]
      textOf pol overflowProgram evs `shouldSatisfy` T.isInfixOf "DINT wraps around (overflow=wrap)"
    it "summarises a FOR loop of 10 iterations: 3 shown, then 7 more, with the for-bounds rule (MT-STMT-19)" $ do
      let evs = traceOf mastertoolXE False 1 forProgram
      [n | Iteration 3 n <- evs] `shouldBe` [1, 2, 3]
      evs `shouldContain` [Elided 3 7, LoopExit 3 10]
      evs `shouldContain` [LoopEnter 3 "I from 1 to 10 by 1"]
      [(dRules d, dPolicy d) | d <- rulesAt 3 evs] `shouldBe` [(["MT-STMT-19"], Just "for-bounds")]
      let text = textOf mastertoolXE forProgram evs
      text `shouldSatisfy` T.isInfixOf "7 more iterations"
      text `shouldSatisfy` T.isInfixOf "(for-bounds=once)"
    it "keeps every iteration with --trace-all" $ do
      let evs = traceOf mastertoolXE True 1 forProgram
      [n | Iteration 3 n <- evs] `shouldBe` [1 .. 10]
      [n | Elided _ n <- evs] `shouldBe` []
      evs `shouldContain` [Wrote 4 "S" "55"]
    it "names the other for-bounds alternative when it is in force" $ do
      let pol = with [("for-bounds", "every-iteration")]
      map dSays (rulesAt 3 (traceOf pol False 1 forProgram)) `shouldBe` ["end and step are evaluated again before every test"]
    it "shows a runtime error with the MT-ERR rule that raised it, and the rule that decided it" $ do
      let src = program ["VAR A : INT; B : INT; END_VAR", "PROGRAM P", "B := 0;", "A := 10 / B;", "END_PROGRAM"]
          evs = traceOf mastertoolXE False 1 src
      [(l, r) | Failure l r _ <- evs] `shouldBe` [(4, Just "MT-ERR-2020")]
      map dRules (rulesAt 4 evs) `shouldBe` [["MT-OP-9"]]
      textOf mastertoolXE src evs `shouldSatisfy` T.isInfixOf "(MT-ERR-2020)"
    it "shows an index out of range: error 2015 under the preset, the element used under clamp (MT-ARR-8)" $ do
      let src = program ["VAR K : INT; V : ARRAY[1..3] OF INT; END_VAR", "PROGRAM P", "K := 5;", "V[K] := 7;", "END_PROGRAM"]
      [r | Failure _ r _ <- traceOf mastertoolXE False 1 src] `shouldBe` [Just "MT-ERR-2015"]
      let evs = traceOf (with [("index-out-of-range", "clamp")]) False 1 src
      evs `shouldContain` [Wrote 4 "V[3]" "7"]
      [(dRules d, dPolicy d) | d <- rulesAt 4 evs] `shouldBe` [(["MT-ARR-8"], Just "index-out-of-range")]
    it "shows the step budget ending an endless loop (MT-EXEC-7, error 2030)" $ do
      let src = program ["VAR X : INT; END_VAR", "PROGRAM P", "WHILE TRUE DO", "X := 1;", "END_WHILE;", "END_PROGRAM"]
          evs = traceOf mastertoolXE {pStepBudget = 100} False 1 src
      [dRules d | Rule _ d <- evs, dPolicy d == Just "step-budget"] `shouldBe` [["MT-EXEC-7"]]
      [r | Failure _ r _ <- evs] `shouldBe` [Just "MT-ERR-2030"]
    it "shows a conversion that wraps (narrow-int, MT-CONV-13)" $ do
      let src = program ["VAR X : INT; Y : DINT; END_VAR", "PROGRAM P", "Y := 70000;", "X := DINT_TO_INT(Y);", "END_PROGRAM"]
          evs = traceOf mastertoolXE False 1 src
      evs `shouldContain` [Wrote 4 "X" "4464"]
      [(dRules d, dPolicy d) | d <- rulesAt 4 evs] `shouldBe` [(["MT-CONV-13"], Just "narrow-int")]
    it "shows a call with its arguments and its result, and the branches of IF and CASE" $ do
      let src =
            program
              [ "VAR A : INT; B : INT; END_VAR" -- 1
              , "FUNCTION TWICE : INT" -- 2
              , "VAR_INPUT X : INT; END_VAR" -- 3
              , "TWICE := X * 2;" -- 4
              , "END_FUNCTION" -- 5
              , "PROGRAM P" -- 6
              , "A := TWICE(3);" -- 7
              , "IF A > 10 THEN B := 1; ELSIF A > 5 THEN B := 2; END_IF;" -- 8
              , "CASE A OF" -- 9
              , "  1..5: B := 3;" -- 10
              , "  6, 7: B := 4;" -- 11
              , "END_CASE;" -- 12
              , "END_PROGRAM" -- 13
              ]
          evs = traceOf mastertoolXE False 1 src
      [Call 7 "TWICE" [("X", "3")], Wrote 4 "TWICE" "6", Return 7 "TWICE" [("TWICE", "6")], Wrote 7 "A" "6"] `shouldSatisfy` all (`elem` evs)
      [b | Branch 8 b <- evs] `shouldBe` ["condition FALSE", "condition TRUE: this ELSIF"]
      [b | Branch 9 b <- evs] `shouldBe` ["selector 6 matches the labels 6, 7"]
      evs `shouldContain` [Wrote 11 "B" "4"]
    it "begins each call with its cycle" $
      [n | Cycle n <- traceOf mastertoolXE False 3 overflowProgram] `shouldBe` [1, 2, 3]
    it "traces a snippet (stref eval --trace) and gives the untraced result" $ do
      let snippet = "VAR I : INT; END_VAR I := 32767 + 1;"
      case (evalSnippetTraced False 1 mastertoolXE snippet, evalSnippet mastertoolXE snippet) of
        (Right (traced, evs), Right plain) -> do
          srResult traced `shouldBe` srResult plain
          [dRules d | Rule _ d <- evs] `shouldContain` [["MT-OP-6"]]
        _ -> expectationFailure "the snippet was rejected"

  describe "a traced run ends as the untraced one" $ do
    -- the corpus is read inside each example, not when the spec tree is
    -- built: held for the whole run, it would slow every later GC (and the
    -- linear-time checks of RobustnessSpec measure CPU time, GC included)
    let withCases check = loadCorpus ["conformance/mastertool-xe"] >>= \corpus -> check [c | Loaded c <- corpusEntries corpus]
        alternatives =
          with
            [ ("overflow", "wrap")
            , ("div-zero", "zero")
            , ("mod-zero", "error")
            , ("index-out-of-range", "clamp")
            , ("for-bounds", "every-iteration")
            , ("for-at-type-max", "follow-overflow-policy")
            , ("short-circuit", "short-circuit")
            , ("narrow-int", "saturate")
            , ("real-to-int", "round-even-wrap")
            , ("arith-width", "promote-32")
            , ("lifetime", "retained")
            ]
    it "on the MasterTool XE corpus (at least 400 cases that run)" $ withCases $ \cases ->
      length [c | c <- cases, Right _ <- [compileSource mastertoolXE (C.caseModule c) (C.caseFile c) (C.caseSource c)]] `shouldSatisfy` (>= 400)
    it "on every case of the corpus, under the preset" $ withCases $ \cases ->
      mapMaybe (differs mastertoolXE) cases `shouldBe` []
    it "on every case of the corpus, under other alternatives of the policies" $ withCases $ \cases ->
      mapMaybe (differs alternatives) cases `shouldBe` []

-- | The case's id when its traced run does not end as its untraced run
-- (the same results of every call, the same final state, or the same
-- failure), with the case's controller, initial operands and calls; the
-- step budget is lowered to keep the traced runs short.
differs :: Policies -> C.Case -> Maybe Text
differs pol0 c = case compileSource pol (C.caseModule c) (C.caseFile c) (C.caseSource c) of
  Left _ -> Nothing
  Right cm ->
    let plain = observed <$> runModule setup cm calls
        traced = observed . fst <$> runModuleTraced False setup cm calls
     in if plain == traced then Nothing else Just (C.caseId c)
  where
    pol = pol0 {pStepBudget = 20000}
    setup = RunSetup pol (C.psConfig (C.casePlc c)) (C.caseModule c) (settings (C.psInit (C.casePlc c)))
    calls = [CallSpec (C.csInputs cs) (settings (C.csSet cs)) [] [] | cs <- C.caseCalls c]
    observed o = (roResults o, roFinal o)
    settings :: [(Operand, C.ExpValue)] -> [(Operand, Setting)]
    settings xs = [(op, s) | (op, v) <- xs, Just s <- [setting v]]
    setting = \case
      C.EInt n -> Just (SetInt n)
      C.EBool b -> Just (SetBool b)
      C.EReal r -> Just (SetReal r)
      C.EBits w -> Just (SetInt (toInteger w))
      _ -> Nothing
