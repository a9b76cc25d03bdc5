-- | The command line as a user meets it: the built executable, its exit codes
-- (0 success, 1 a negative answer, 2 a usage error, 3 the last line of
-- defence) and its output formats.
-- Expected values come from the rules, not from earlier runs: 15000 + 25000
-- on INT saturates to 32767 with INTERNAL_OVERFLOW (MT-OP-6, MT-OP-7); a
-- division by zero is runtime error 2020 at the line of the division
-- (MT-OP-9, MT-DIAG-2); a successful call leaves [-32768, 0, 0, 0, 0] in the
-- diagnostic band (MT-DIAG-4).
module CliSpec (spec) where

import Conformance.Paths (engineScript, fixtureCorpus, strefBinary)
import Data.Aeson (Value (..), decode)
import qualified Data.Aeson.Key as Key
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (intercalate, isInfixOf, isPrefixOf)
import qualified Data.Vector as V
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import Control.Exception (evaluate)
import System.IO (hClose, hGetContents, hGetLine)
import System.Environment (getEnvironment)
import System.Process (CreateProcess (..), StdStream (..), createProcess, proc, readCreateProcessWithExitCode, readProcessWithExitCode, waitForProcess)
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

  describe "run --watch and --scenario" $ do
    it "an IEC program: a row per cycle, a column per watched variable (a path, or a name of the program), driven by a scenario of set and numbers of cycles" $ do
      (code, out, _) <- stref ["run", "--dialect", "tecomat", fixture "tecomat-counter.st", "--scenario", fixture "tecomat-counter-scenario.yaml", "--watch", "MAIN.cnt", "--watch", "t.Q", "--watch", "t.ET"]
      code `shouldBe` ExitSuccess
      -- TON with PT = T#20ms, IN from cycle 1 (clock 0) to 4: Q at clock 20 (TC-FB-27), reset by IN FALSE in cycle 5
      map words (lines out)
        `shouldContain` [ ["cycle", "clock", "MAIN.cnt", "t.Q", "t.ET"]
                        , ["1", "T#0ms", "1", "FALSE", "T#0ms"]
                        , ["2", "T#10ms", "2", "FALSE", "T#10ms"]
                        , ["3", "T#20ms", "3", "TRUE", "T#20ms"]
                        , ["4", "T#30ms", "4", "TRUE", "T#20ms"]
                        , ["5", "T#40ms", "5", "FALSE", "T#0ms"]
                        , ["6", "T#50ms", "6", "FALSE", "T#0ms"]
                        ]
    it "a MasterTool XE module: variables and operands, INTERNAL_OVERFLOW, the runtime error, and a call with INPUT1 FALSE" $ do
      (code, out, _) <- stref ["run", fixture "watch-mastertool.st", "--scenario", fixture "watch-mastertool-scenario.yaml", "--watch", "CNT", "--watch", "%M0006.6"]
      code `shouldBe` ExitSuccess
      -- CNT := CNT + 10000 from 5; the module does not run in call 2; 29995 + 10000 saturates (MT-OP-6)
      map words (take 4 (lines out))
        `shouldBe` [ ["call", "CNT", "%M0006.6", "INTERNAL_OVERFLOW", "error"]
                   , ["1", "10005", "FALSE", "FALSE"]
                   , ["2", "-", "FALSE", "FALSE", "not", "executed", "(INPUT1", "FALSE)"]
                   , ["3", "32767", "TRUE", "FALSE"]
                   ]
    it "--calls 3 shows the runtime error of the call that raised it" $ do
      (code, out, _) <- stref ["run", fixture "watch-mastertool.st", "--calls", "3", "--watch", "CNT"]
      code `shouldBe` ExitFailure 1
      map words (lines out) `shouldContain` [["3", "30000", "FALSE", "2020", "at", "line", "9"]]
    it "a name that names nothing is a usage error, exit 2, for both models" $ do
      (code, _, err) <- stref ["run", fixture "watch-mastertool.st", "--watch", "NOPE"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("--watch NOPE: no variable or operand of that name" `isInfixOf`)
      (code', _, err') <- stref ["run", "--dialect", "tecomat", fixture "tecomat-counter.st", "--watch", "nope"]
      code' `shouldBe` ExitFailure 2
      err' `shouldSatisfy` ("--watch nope: no variable of that name" `isInfixOf`)
    it "an unknown key in a scenario names the file, its line, the key and the valid keys, exit 2" $ do
      (code, _, err) <- stref ["run", "--dialect", "tecomat", fixture "tecomat-counter.st", "--scenario", fixture "bad-scenario.yaml"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ((fixture "bad-scenario.yaml" <> ":2: calls[1].bogus: unknown key 'bogus'; the keys here are: set, reset") `isInfixOf`)
  describe "messages a PLC engineer understands" $ do
    it "a missing END_IF: IEC dialects report it at the IF, saying where the parser noticed" $ do
      (code, _, err) <- stref ["check", "--dialect", "tecomat", fixture "if-not-closed.st"]
      code `shouldBe` ExitFailure 1
      err `shouldSatisfy` ("if-not-closed.st:5:3: error: this IF is not closed: END_IF is missing (the parser reached 'END_WHILE' at line 7, column 1 while looking for it)" `isInfixOf`)
    it "MasterTool XE keeps MT-VERR-4's place (where the parser noticed) and names the IF left open" $ do
      (code, _, err) <- stref ["check", fixture "if-not-closed.st"]
      code `shouldBe` ExitFailure 1
      err `shouldSatisfy` ("if-not-closed.st:7:1: error: expected END_IF instead of 'END_WHILE': the IF at line 5, column 3 is not closed" `isInfixOf`)
    it "eval errors point into the snippet, not into its wrapper" $ do
      (_, _, err) <- stref ["eval", "VAR x : INT; END_VAR x := y + 1;"]
      err `shouldSatisfy` ("<snippet>:1:27: error: the variable y is not declared" `isInfixOf`)
      (_, _, err') <- stref ["eval", "--dialect", "tecomat", "VAR x : INT; END_VAR IF x > 0 THEN x := 1;"]
      err' `shouldSatisfy` ("<snippet>:1:22: error: this IF is not closed: END_IF is missing (the parser reached the end of the snippet while looking for it)" `isInfixOf`)
    it "another dialect's construct says which dialect has it" $ do
      (_, _, err) <- stref ["eval", "VAR t1 : TON; END_VAR"]
      err `shouldSatisfy` ("TON is a standard function block of IEC 61131-3; MasterTool XE has no function blocks (--dialect tecomat and nexto have them)" `isInfixOf`)
      (_, _, err') <- stref ["eval", "VAR x : INT; END_VAR x := 1; // set"]
      err' `shouldSatisfy` ("MasterTool XE has no // comments: write (* ... *)" `isInfixOf`)
      (_, _, err'') <- stref ["eval", "--dialect", "tecomat", "VAR i : INT; END_VAR WHILE i < 3 DO i := i + 1; CONTINUE; END_WHILE;"]
      err'' `shouldSatisfy` ("CONTINUE is a CODESYS extension, not part of this dialect: --dialect nexto has it" `isInfixOf`)
  describe "check --portability" $ do
    it "lists, for an IEC program, each construct a policy decides, with file:line:col, the policy and its alternative here, and the rule ids; exit 0" $ do
      (code, out, _) <- stref ["check", "--dialect", "tecomat", "--portability", fixture "portability-tecomat.st"]
      code `shouldBe` ExitSuccess
      let ws = filter ("warning:" `isInfixOf`) (lines out)
      length ws `shouldBe` 12
      out `shouldSatisfy` ("portability-tecomat.st:20:1: warning: cnt + a constant, stored back in cnt" `isInfixOf`)
      out `shouldSatisfy` ("[policy overflow (here wrap); rules TC-OP-20]" `isInfixOf`)
      out `shouldSatisfy` (":21:15: warning: the loop's body writes a variable of this bound" `isInfixOf`)
      out `shouldSatisfy` ("[policy short-circuit (here eager); rules TC-OP-6]" `isInfixOf`)
      out `shouldSatisfy` ("12 portability warnings" `isInfixOf`)
    it "cites the nexto catalogue's ids under nexto, and gives JSON with --format json" $ do
      (code, out, _) <- stref ["check", "--dialect", "nexto", "--portability", "--format", "json", fixture "portability-tecomat.st"]
      code `shouldBe` ExitSuccess
      out `shouldSatisfy` ("\"rules\":[\"NX-OP-32\",\"NX-ERR-24\"]" `isInfixOf`)
      out `shouldSatisfy` ("{\"alternative\":\"false\",\"policy\":\"f-trig-initial\"}" `isInfixOf`)
    it "lists them for a MasterTool XE module: a local named like a global (MT-SCOPE-5), an accumulator (MT-OP-6), a FOR bound written in the body (MT-STMT-19)" $ do
      (code, out, _) <- stref ["check", "--portability", fixture "portability-mastertool.st"]
      code `shouldBe` ExitSuccess
      out `shouldSatisfy` ("portability-mastertool.st:10:3: warning: g is also the name of a global" `isInfixOf`)
      out `shouldSatisfy` ("[policy name-resolution (here global-wins); rules MT-SCOPE-5]" `isInfixOf`)
      out `shouldSatisfy` (":18:1: warning: g + a constant" `isInfixOf`)
      out `shouldSatisfy` ("[policy for-bounds (here once); rules MT-STMT-19]" `isInfixOf`)
      out `shouldSatisfy` ("14 portability warnings" `isInfixOf`)
    it "says nothing without --portability" $ do
      (_, out, _) <- stref ["check", fixture "portability-mastertool.st"]
      out `shouldNotSatisfy` ("warning" `isInfixOf`)
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

  describe "an IEC dialect (--dialect tecomat)" $ do
    it "runs a program over cycles and prints its variables: the counter counts cycles (TC-POU-15), TON's ET reads the clock (TC-FB-27)" $ do
      (code, out, _) <- stref ["run", "--dialect", "tecomat", fixture "tecomat-counter.st", "--calls", "4", "--set", "MAIN.start=TRUE"]
      code `shouldBe` ExitSuccess
      lines out `shouldSatisfy` (\ls -> all (`elem` ls) ["  MAIN.cnt = 4", "  MAIN.t.Q = TRUE", "  MAIN.t.ET = T#20ms"])
      out `shouldSatisfy` ("cycles run: 4" `isInfixOf`)
    it "parse lists the declarations of a unit" $ do
      (code, out, _) <- stref ["parse", "--dialect", "tecomat", fixture "tecomat-counter.st"]
      code `shouldBe` ExitSuccess
      lines out `shouldBe` ["PROGRAM MAIN (2 statements)"]
    it "prints the same as JSON" $ do
      (code, out, _) <- stref ["run", "--dialect", "tecomat", fixture "tecomat-counter.st", "--calls", "2", "--format", "json"]
      code `shouldBe` ExitSuccess
      (decode (BL.pack out) >>= field ["vars", "MAIN.cnt"]) `shouldBe` Just (Number 2)
    it "rejects a type mismatch with file, line, column and kind, exit 1 (TC-CONV-3)" $ do
      (code, _, err) <- stref ["check", "--dialect", "tecomat", fixture "tecomat-mismatch.st"]
      code `shouldBe` ExitFailure 1
      err `shouldSatisfy` ("tecomat-mismatch.st:3:6: error:" `isInfixOf`)
      err `shouldSatisfy` ("[type-mismatch]" `isInfixOf`)
    it "accepts the same file under implicit-conversions=iec-widening" $ do
      (code, _, _) <- stref ["check", "--dialect", "tecomat", "--policy", "implicit-conversions=iec-widening", fixture "tecomat-mismatch.st"]
      code `shouldBe` ExitSuccess
    it "evaluates a snippet as the body of PROGRAM MAIN, over cycles" $ do
      (code, out, _) <- stref ["eval", "--dialect", "tecomat", "--calls", "2", "VAR x : SINT := 126; END_VAR x := x + 1;"]
      code `shouldBe` ExitSuccess
      lines out `shouldContain` ["  MAIN.x = -128"]
    it "eval --compare shows a snippet under every alternative of a policy, marking what differs (TC-OP-20)" $ do
      (code, out, _) <- stref ["eval", "--dialect", "tecomat", "--compare", "overflow", "VAR x : SINT := 127; y : INT; END_VAR x := x + 1; y := 3;"]
      code `shouldBe` ExitSuccess
      map words (lines out) `shouldContain` [["*", "MAIN.x", "127", "-128", "127"], ["*", "MAIN.y", "3", "3", "0"]]
    it "eval --calls N calls a MasterTool XE snippet N times: mapped operands keep their values, locals start again (MT-EXEC-9)" $ do
      (code, out, _) <- stref ["eval", "--calls", "3", "VAR A AT %M0010 : INT; B : INT; END_VAR A := A + 1; B := B + 1;"]
      code `shouldBe` ExitSuccess
      lines out `shouldContain` ["A = 3", "B = 1"]
      (_, traced, _) <- stref ["eval", "--calls", "2", "--trace", "VAR A AT %M0010 : INT; END_VAR A := A + 1;"]
      lines traced `shouldContain` ["cycle 2"]
      (code0, _, err0) <- stref ["eval", "--calls", "0", "VAR A : INT; END_VAR A := 1;"]
      code0 `shouldBe` ExitFailure 2
      err0 `shouldSatisfy` ("--calls takes a number of module calls from 1" `isInfixOf`)
    it "explore --compare finds generated programs whose result depends on the overflow policy and shrinks one to a few lines (TC-OP-20)" $ do
      (code, out, _) <- stref ["explore", "--dialect", "tecomat", "--compare", "overflow", "--count", "50", "--seed", "7"]
      code `shouldBe` ExitFailure 1
      out `shouldSatisfy` ("overflow=wrap gives" `isInfixOf`)
      length (takeWhile (/= "END_PROGRAM") (dropWhile (/= "PROGRAM MAIN") (lines out))) `shouldSatisfy` (<= 12)
    it "explore --exclude-feature leaves a part of the language out of the programs, and a name it never uses is a usage error" $ do
      (code, out, _) <- stref ["explore", "--dialect", "tecomat", "--print", "--count", "5", "--seed", "1", "--exclude-feature", "real", "--exclude-feature", "time", "--exclude-feature", "for"]
      code `shouldBe` ExitSuccess
      out `shouldSatisfy` ("the programs use only types BOOL, SINT, INT, DINT, USINT, UINT, BYTE, WORD; statements assignment, IF, CASE, CTU calls;" `isInfixOf`)
      out `shouldNotSatisfy` (\o -> any (`isInfixOf` o) ["REAL", "TIME", "FOR ", "TON"])
      (code', _, err) <- stref ["explore", "--dialect", "tecomat", "--print", "--exclude-feature", "timer"]
      code' `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("--exclude-feature timer: the generated programs never use it; the features they can do without: bool," `isInfixOf`)
      (code'', _, err'') <- stref ["explore", "--print", "--exclude-feature", "real"]
      code'' `shouldBe` ExitFailure 2
      err'' `shouldSatisfy` ("restrict the IEC dialects' programs" `isInfixOf`)
    describe "the trace (docs/trace.md)" $ do
      it "eval --trace shows each statement with the values read and written, and the overflow rule with the alternative in force (TC-OP-20)" $ do
        (code, out, _) <- stref ["eval", "--dialect", "tecomat", "--trace", "VAR x : SINT := 127; y : SINT; END_VAR y := x + 1;"]
        code `shouldBe` ExitSuccess
        out `shouldSatisfy` ("y := x + 1;" `isInfixOf`)
        out `shouldSatisfy` ("x = 127; -> y := -128" `isInfixOf`)
        out `shouldSatisfy` ("rule TC-OP-20: 127 + 1 = 128 lies outside SINT: the result is -128 (overflow=wrap)" `isInfixOf`)
      it "run --trace --format json prints one JSON event per line, then the result" $ do
        (code, out, _) <- stref ["run", "--dialect", "tecomat", "--trace", "--format", "json", fixture "tecomat-counter.st"]
        code `shouldBe` ExitSuccess
        take 1 (lines out) `shouldBe` ["{\"cycle\":1,\"event\":\"cycle\"}"]
        lines out `shouldSatisfy` all (\l -> take 1 l == "{")
        last (lines out) `shouldSatisfy` ("\"vars\"" `isInfixOf`)
      it "--trace --watch keeps only the statements that read or write the name" $ do
        (_, out, _) <- stref ["eval", "--dialect", "tecomat", "--trace", "--watch", "y", "VAR x : INT; y : INT; END_VAR x := 1; y := 2; x := 3;"]
        out `shouldSatisfy` ("-> y := 2" `isInfixOf`)
        out `shouldNotSatisfy` ("-> x := 3" `isInfixOf`)
      it "eval --compare POLICY --trace shows both traces from the first point where they part (TC-OP-20)" $ do
        (code, out, _) <- stref ["eval", "--dialect", "tecomat", "--compare", "overflow", "--trace", "VAR x : SINT := 120; y : SINT; END_VAR y := 1; x := x + 10; y := x;"]
        code `shouldBe` ExitSuccess
        out `shouldSatisfy` ("agree on the first 2 trace items" `isInfixOf`)
        out `shouldSatisfy` ("under overflow=saturate:" `isInfixOf`)
        out `shouldSatisfy` ("x = 120; -> x := 127" `isInfixOf`)
        out `shouldSatisfy` ("x = 120; -> x := -126" `isInfixOf`)
        out `shouldSatisfy` ("a runtime error (overflow=trap)" `isInfixOf`)
      it "conformance CASE --explain prints the reference's trace of the case before the report" $ do
        (code, out, _) <- stref ["conformance", "--explain", "conformance/tecomat/statements/for-default-step-one.st"]
        code `shouldBe` ExitSuccess
        out `shouldSatisfy` ("the reference's trace of tecomat/statements/for-default-step-one" `isInfixOf`)
        out `shouldSatisfy` ("rule TC-STMT-26, TC-STMT-27" `isInfixOf`)
        out `shouldSatisfy` ("1 passed" `isInfixOf`)
      it "MasterTool XE: run --trace cites MT-OP-6 with the alternative in force, and the runtime error's rule (MT-ERR-2020)" $ do
        (code, out, _) <- stref ["run", "--trace", fixture "trace-scaled.st"]
        code `shouldBe` ExitFailure 1
        out `shouldSatisfy` ("ACC = 2147483000, V[10] = 30; -> ACC := 2147483647" `isInfixOf`)
        out `shouldSatisfy` ("rule MT-OP-6: 2147483000 + 900 = 2147483647: DINT saturates (overflow=saturate)" `isInfixOf`)
        out `shouldSatisfy` ("runtime error: 2020, division by zero (MT-ERR-2020)" `isInfixOf`)
        out `shouldSatisfy` ("... 7 more iterations not shown" `isInfixOf`)
      it "MasterTool XE: conformance CASE --explain, with an engine that differs, shows the trace and the differences" $ do
        bin <- strefBinary
        (code, out, _) <- stref ["conformance", "--explain", "--engine", bin <> " engine --policy overflow=wrap", "conformance/mastertool-xe/operators/associativity-with-saturation.st"]
        code `shouldBe` ExitFailure 1
        out `shouldSatisfy` ("rule MT-OP-6: 32767 + 1 = 32767: INT saturates (overflow=saturate)" `isInfixOf`)
        out `shouldSatisfy` ("FAIL mastertool-xe/operators/associativity-with-saturation: %M0030: expected 32766, got 32767" `isInfixOf`)
      it "conformance --explain needs exactly one case, exit 2" $ do
        (code, _, err) <- stref ["conformance", "--explain", "conformance/tecomat/statements"]
        code `shouldBe` ExitFailure 2
        err `shouldSatisfy` ("--explain explains one case" `isInfixOf`)
    it "names an unknown dialect with the known ones, exit 2" $ do
      (code, _, err) <- stref ["run", "--dialect", "codesys", fixture "tecomat-counter.st"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("tecomat" `isInfixOf`)

  describe "nexto: rule ids, ADR and pointers into direct addresses" $ do
    it "a reserved name cites the rules of the dialect's own catalogue (NX-LEX-12 under nexto, TC-LEX-3 under tecomat)" $ do
      (code, _, err) <- stref ["check", "--dialect", "nexto", fixture "nexto-reserved.st"]
      code `shouldBe` ExitFailure 1
      err `shouldSatisfy` ("(NX-LEX-12, NX-LEX-13) [reserved-name]" `isInfixOf`)
      (_, _, errT) <- stref ["check", "--dialect", "tecomat", fixture "nexto-reserved.st"]
      errT `shouldSatisfy` ("(TC-LEX-1, TC-LEX-3) [reserved-name]" `isInfixOf`)
    it "ADR of a BOOL at a bit address is rejected: a pointer reaches bytes, not bits" $ do
      (code, _, err) <- stref ["check", "--dialect", "nexto", fixture "adr-of-a-bit.st"]
      code `shouldBe` ExitFailure 1
      err `shouldSatisfy` ("6:6: error: ADR gives the address of a byte, and %QX0.3 is one bit of it" `isInfixOf`)
    it "a pointer into %M writes only the bytes of the member it reaches, at its packed offset (docs/nexto.md, the memory model)" $ do
      (code, out, _) <- stref ["run", "--dialect", "nexto", fixture "area-pointer-packed.st"]
      code `shouldBe` ExitSuccess
      -- Rec packed: flag at 0, count at 1..2, tail at 3; raw holds bytes 20..23, guard byte 24
      lines out `shouldContain` ["  MAIN.guard = 99", "  MAIN.p = 671088660", "  MAIN.gotCount = 258", "  MAIN.off = 1"]
    it "tasks of different intervals: the default cycle is their greatest common divisor, each runs when its interval comes round; a program WITH an unknown task is rejected (TC-CFG-10)" $ do
      (code, out, _) <- stref ["run", "--dialect", "nexto", fixture "tasks-two-intervals.st", "--calls", "4"]
      code `shouldBe` ExitSuccess
      -- 40 ms and 60 ms: a 20 ms cycle, clock 0, 20, 40, 60
      take 1 (lines out) `shouldBe` ["cycles run: 4 (cycle T#20ms, clock at the last cycle T#60ms)"]
      lines out `shouldContain` ["  fastRuns = 2", "  slowRuns = 2"]
      (codeU, _, errU) <- stref ["check", "--dialect", "nexto", fixture "tasks-unknown-task.st"]
      codeU `shouldBe` ExitFailure 1
      errU `shouldSatisfy` ("which is not a TASK of its resource (TC-CFG-10) [undeclared-task]" `isInfixOf`)
    it "a type mismatch cites the conversion rules of the dialect's catalogue (NX-CONV-1 under nexto, TC-CONV-1 under tecomat)" $ do
      (_, _, errN) <- stref ["check", "--dialect", "nexto", fixture "narrowing.st"]
      errN `shouldSatisfy` ("convert it explicitly (NX-CONV-1, NX-CONV-2) [type-mismatch]" `isInfixOf`)
      (_, _, errT) <- stref ["check", "--dialect", "tecomat", fixture "narrowing.st"]
      errT `shouldSatisfy` ("convert it explicitly (TC-CONV-1, TC-CONV-3) [type-mismatch]" `isInfixOf`)
    it "a runtime error cites the rule by the dialect's catalogue: the watchdog (NX-ERR-26 under nexto, TC-ERR-1 under tecomat)" $ do
      (codeN, outN, _) <- stref ["run", "--dialect", "nexto", "--policy", "step-budget=1000", fixture "endless.st"]
      codeN `shouldBe` ExitFailure 1
      outN `shouldSatisfy` ("the watchdog ends it (cycle error, NX-ERR-26)" `isInfixOf`)
      (_, outT, _) <- stref ["run", "--dialect", "tecomat", "--policy", "step-budget=1000", fixture "endless.st"]
      outT `shouldSatisfy` ("the watchdog ends it (cycle error, TC-ERR-1)" `isInfixOf`)

  describe "run" $ do
    it "says on each call's line when the call leaves INTERNAL_OVERFLOW set (MT-OP-7)" $ do
      (_, out, _) <- stref ["run", fixture "sat.st", "--set", "%M0010=15000", "--set", "%M0011=25000"]
      take 1 (lines out) `shouldBe` ["call 1: ok, INTERNAL_OVERFLOW set (2 steps)"]
      (_, quiet, _) <- stref ["run", fixture "sat.st", "--set", "%M0010=1", "--set", "%M0011=2"]
      take 1 (lines quiet) `shouldBe` ["call 1: ok (2 steps)"]
    it "--compare POLICY runs a MasterTool XE file under every alternative, over all its calls, and says after which call they part (MT-OP-6, MT-OP-7)" $ do
      (code, out, _) <- stref ["run", fixture "accumulate-mastertool.st", "--compare", "overflow", "--calls", "5"]
      code `shouldBe` ExitFailure 1
      map words (lines out) `shouldContain` [["*", "TOTAL", "overflow=saturate:", "32767", "overflow=wrap:", "-15536", "overflow=trap:", "30000"]]
      out `shouldSatisfy` ("error under overflow=trap: runtime error 9001 (integer overflow (trap policy)) at line 6, complements 0 0 0 in call 4" `isInfixOf`)
      lines out `shouldContain` ["they part after call 4"]
      (code3, out3, _) <- stref ["run", fixture "accumulate-mastertool.st", "--compare", "overflow", "--calls", "3"]
      code3 `shouldBe` ExitSuccess
      lines out3 `shouldContain` ["the variants agree after every call"]
      -- in constant memory: 10^5 calls in a 32 MB heap (they held every call's state: 270 MB)
      (codeM, outM, errM) <- stref ["run", fixture "accumulate-mastertool.st", "--compare", "overflow", "--calls", "100000", "+RTS", "-M32m", "-RTS"]
      (codeM, errM) `shouldBe` (ExitFailure 1, "")
      lines outM `shouldContain` ["they part after call 4"]
      (codeP, _, errP) <- stref ["run", fixture "accumulate-mastertool.st", "--presets", "tecomat"]
      codeP `shouldBe` ExitFailure 2
      errP `shouldSatisfy` ("compare the alternatives of a policy with --compare POLICY" `isInfixOf`)
    it "says, for a CHF parameter error, the counts expected and given (2009, 2010) or which parameter (MT-PARAM-3..7)" $ do
      (code, out, _) <- stref ["run", "--module", "F", fixture "chf-scale.st", "--in", "%M0010", "--out", "%M0020"]
      code `shouldBe` ExitFailure 1 -- a call ended in a runtime error
      out `shouldSatisfy` ("runtime error 2009 (incorrect number of input parameters) at line 0, complements 0 0 0: SCALE has 2 input parameters (RAW, GAIN), the call gives 1" `isInfixOf`)
      (_, out', _) <- stref ["run", "--module", "F", fixture "chf-scale.st", "--in", "%M0010", "--in", "%KM+3", "--out", "%M0020", "--out", "%M0021"]
      out' `shouldSatisfy` ("SCALE has 1 output parameter (OUT), the call gives 2" `isInfixOf`)
      (_, out'', _) <- stref ["run", "--module", "F", fixture "chf-scale.st", "--in", "%M0010", "--in", "%KF+3.0", "--out", "%M0020"]
      out'' `shouldSatisfy` ("runtime error 2003 (incorrect input parameter) at line 0, complements 2 0 0: input parameter 2 is GAIN" `isInfixOf`)
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
    it "--presets runs an IEC program under each preset, marks what differs and says after which cycle they part; exit 1" $ do
      (code, out, _) <- stref ["run", fixture "engine-presets.st", "--dialect", "tecomat", "--calls", "5", "--presets", "tecomat", "--presets", "ironplc"]
      code `shouldBe` ExitFailure 1
      lines out `shouldContain` ["* MAIN.mean  tecomat: -12768  ironplc: 20000"]
      lines out `shouldContain` ["they part after cycle 1"]
    it "--compare POLICY runs every alternative; variants that part and agree again by the last cycle still exit 1, with the cycle" $ do
      (code, out, _) <- stref ["run", fixture "engine-presets.st", "--dialect", "tecomat", "--calls", "5", "--compare", "timer-q", "--format", "json"]
      code `shouldBe` ExitFailure 1
      let j = decode (BL.pack out) :: Maybe Value
      (j >>= field ["first_parting_cycle"]) `shouldBe` Just (Number 4)
      (j >>= field ["differ"]) `shouldBe` Just (Array V.empty)
      (j >>= field ["vars", "MAIN.mean", "timer-q=next-cycle"]) `shouldBe` Just (String "-12768")
    it "--presets needs two IEC presets; an unknown policy is named" $ do
      (code, _, err) <- stref ["run", fixture "engine-presets.st", "--dialect", "tecomat", "--presets", "tecomat"]
      code `shouldBe` ExitFailure 2
      err `shouldContain` "at least two presets"
      (code2, _, err2) <- stref ["run", fixture "engine-presets.st", "--dialect", "tecomat", "--compare", "no-such-policy"]
      code2 `shouldBe` ExitFailure 2
      err2 `shouldContain` "no policy 'no-such-policy'"
      (code3, _, err3) <- stref ["run", fixture "engine-presets.st", "--dialect", "tecomat", "--presets", "tecomat", "--presets", "mastertool-xe"]
      code3 `shouldBe` ExitFailure 2
      err3 `shouldContain` "MasterTool XE controller's preset"
    it "a rejected program under --format json is a JSON verdict on stdout, for MasterTool XE and the IEC dialects; exit 1" $ do
      (code, out, _) <- stref ["run", fixture "syntax-error.st", "--format", "json"]
      code `shouldBe` ExitFailure 1
      let j = decode (BL.pack out) :: Maybe Value
      (j >>= field ["verdict"]) `shouldBe` Just (String "rejected")
      (code', out', _) <- stref ["run", fixture "tecomat-mismatch.st", "--dialect", "tecomat", "--format", "json"]
      code' `shouldBe` ExitFailure 1
      (decode (BL.pack out') >>= field ["errors"]) `shouldSatisfy` \case
        Just (Array es) -> fmap (field ["kind"]) (V.toList es) == [Just (String "type-mismatch")]
        _ -> False
    it "a --plc file with an unknown key names it and the valid ones; a missing one says so; exit 2" $ do
      (code, _, err) <- stref ["run", fixture "sat.st", "--plc", fixture "plc-unknown-key.yaml"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` isInfixOf "unknown key 'declar'; the keys are declare, diagnostics, init, chf"
      (code', _, err') <- stref ["run", fixture "sat.st", "--plc", fixture "no-such-plc.yaml"]
      code' `shouldBe` ExitFailure 2
      err' `shouldSatisfy` isInfixOf "no such file: "
    it "a missing file or a directory is said in words, exit 2" $ do
      (code, _, err) <- stref ["run", "no-such-dir/prog.st"]
      code `shouldBe` ExitFailure 2
      err `shouldBe` "stref run: no such file: no-such-dir/prog.st\n"
      (code', _, err') <- stref ["check", "test"]
      code' `shouldBe` ExitFailure 2
      err' `shouldBe` "stref check: test is a directory, not an ST file\n"
    it "stops at a division by zero with error 2020 on its line and exits 1" $ do
      (code, out, _) <- stref ["run", fixture "divzero.st", "--set", "%M0010=5", "--format", "json"]
      code `shouldBe` ExitFailure 1
      let j = decode (BL.pack out) :: Maybe Value
      (j >>= field ["diagnostics"]) `shouldBe` Just (Array (V.fromList (map Number [8, 2020, 0, 0, 0])))
      -- the write before the error persists (MT-EXEC-8)
      (j >>= field ["operands", "%M0012"]) `shouldBe` Just (Number 7)
      (j >>= field ["outputs", "OUTPUT1"]) `shouldBe` Just (Bool False)

    -- scan-mastertool.st: COUNT := COUNT + 1 saturates at 32767
    -- (MT-OP-6); in the last call T = 32767 MOD 16 = 15, so the IF body is
    -- skipped: five assignments and the IF test are 6 steps. A heap of 16 MB
    -- holds the run only if the calls are not all kept until the end (they
    -- were: 58 MB for 10^5 calls).
    it "runs 10^5 calls in constant memory, as text" $ do
      (code, out, err) <- stref ["run", fixture "scan-mastertool.st", "--calls", "100000", "+RTS", "-M16m", "-RTS"]
      (code, err) `shouldBe` (ExitSuccess, "")
      -- the calls, "operands changed:", four operands, outputs, diagnostics
      length (lines out) `shouldBe` 100000 + 7
      take 2 (drop 99999 (lines out)) `shouldBe` ["call 100000: ok (6 steps)", "operands changed:"]
      lines out `shouldContain` ["  %M0200        32767  (16#7FFF)"]
    it "runs 10^5 calls in constant memory, as JSON" $ do
      (code, out, err) <- stref ["run", fixture "scan-mastertool.st", "--calls", "100000", "--format", "json", "+RTS", "-M16m", "-RTS"]
      (code, err) `shouldBe` (ExitSuccess, "")
      let j = decode (BL.pack out) :: Maybe Value
      fmap (\case Array calls -> V.length calls; _ -> 0) (j >>= field ["calls"]) `shouldBe` Just 100000
      (j >>= field ["operands", "%M0200"]) `shouldBe` Just (Number 32767)
      (j >>= field ["vars", "SCAN.T"]) `shouldBe` Just (Number 15)

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

  describe "a reader that goes away" $
    -- 10^5 call lines are far more than a pipe holds, so stref is still
    -- writing when the reader closes its end: it must stop quietly with the
    -- status of SIGPIPE (docs/robustness.md), not report an internal error
    it "ends stref quietly with exit status 141" $ do
      bin <- strefBinary
      (_, Just out, Just err, ph) <-
        createProcess (proc bin ["run", fixture "scan-mastertool.st", "--calls", "100000"]) {std_out = CreatePipe, std_err = CreatePipe}
      firstLine <- hGetLine out
      hClose out
      errText <- hGetContents err
      _ <- evaluate (length errText)
      code <- waitForProcess ph
      firstLine `shouldBe` "call 1: ok (6 steps)"
      code `shouldBe` ExitFailure 141
      errText `shouldBe` ""

  describe "conformance: a selection that matches nothing is a usage error" $ do
    it "names each --rule, --feature and --filter value that matched no case, exit 2" $ do
      (code, out, err) <- stref ["conformance", fixtureCorpus, "--rule", "TC-NOPE-1", "--feature", "calls", "--feature", "no-such-feature", "--filter", "*/nope/*"]
      code `shouldBe` ExitFailure 2
      lines err `shouldBe`
        [ "stref conformance: --filter */nope/* matches no case id"
        , "stref conformance: --feature no-such-feature matches no case"
        , "stref conformance: --rule TC-NOPE-1 matches no case"
        ]
      out `shouldBe` ""
    it "says so when each value matches some case but none matches all, exit 2" $ do
      -- MT-OP-7 is cited only by arith/int-add-saturates, the feature calls only by calls/three-calls
      (code, _, err) <- stref ["conformance", fixtureCorpus, "--rule", "MT-OP-7", "--feature", "calls"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` isInfixOf "the selection --feature calls --rule MT-OP-7 matches no case"
    it "--exclude-feature and --features-file: an engine's missing features make their cases unsupported, without asking it" $ do
      -- the engine would fail every case: only the cases not excluded reach it
      (code, out, _) <- stref ["conformance", fixtureCorpus, "--exclude-feature", "real", "--engine", "false"]
      code `shouldBe` ExitFailure 1
      last (lines out) `shouldBe` "0 passed, 0 failed, 2 unsupported, 4 engine-error, 0 skipped"
      (code', out', _) <- stref ["conformance", fixtureCorpus, "--features-file", fixture "lacks-real.features"]
      code' `shouldBe` ExitSuccess
      last (lines out') `shouldBe` "4 passed, 0 failed, 2 unsupported, 0 engine-error, 0 skipped"
      (code'', _, err'') <- stref ["conformance", fixtureCorpus, "--exclude-feature", "reel"]
      code'' `shouldBe` ExitFailure 2
      err'' `shouldSatisfy` isInfixOf "--exclude-feature reel matches no case"
    it "runs a selection that matches, also in a shard that holds none of its cases" $ do
      (code, out, _) <- stref ["conformance", fixtureCorpus, "--rule", "MT-OP-7"]
      code `shouldBe` ExitSuccess
      last (lines out) `shouldBe` "1 passed, 0 failed, 0 unsupported, 0 engine-error, 5 skipped"
      -- shard 2/3 holds arith/real-rounding and calls/named-vars
      (code', out', _) <- stref ["conformance", fixtureCorpus, "--rule", "MT-OP-7", "--shard", "2/3"]
      code' `shouldBe` ExitSuccess
      last (lines out') `shouldBe` "0 passed, 0 failed, 0 unsupported, 0 engine-error, 2 skipped"

  describe "conformance: failures first" $ do
    -- the canned engine answers every case as int-add-saturates expects:
    -- %M0012 = 32767, %M0013.0 = TRUE, OUTPUT1 = TRUE, no error
    let canned = ["conformance", fixtureCorpus, "--engine", engineScript "canned"]
    it "lists every difference of a failing case in the text report" $ do
      (code, out, _) <- stref canned
      code `shouldBe` ExitFailure 1
      -- three-calls expects %M0101 = 2 and OUTPUT1 = FALSE (its last call's INPUT1)
      let afterHeader = drop 1 (dropWhile (not . isInfixOf "FAIL mastertool-xe/calls/three-calls:") (lines out))
      lines out `shouldContain` ["FAIL mastertool-xe/calls/three-calls: %M0101: expected 2, got not reported"]
      take 1 afterHeader `shouldBe` ["  OUTPUT1: expected false, got true"]
    it "shows the rules a failing case cites, with their titles from RULES" $ do
      (_, out, _) <- stref canned
      let afterHeader = drop 1 (dropWhile (not . isInfixOf "FAIL mastertool-xe/calls/three-calls:") (lines out))
      take 2 afterHeader `shouldBe` ["  OUTPUT1: expected false, got true", "  rule MT-EXEC-9: a module call runs the program once"]
    it "--only-failures lists only the cases that fail the run, with the same totals" $ do
      (_, full, _) <- stref (canned ++ ["--verbose", "--known-failures", "test/fixtures/known-failures-canned"])
      (code, out, _) <- stref (canned ++ ["--verbose", "--known-failures", "test/fixtures/known-failures-canned", "--only-failures"])
      code `shouldBe` ExitSuccess
      -- the one that passes and the five known failures are listed without the option, not with it
      lines full `shouldContain` ["PASS mastertool-xe/arith/int-add-saturates"]
      length (filter (isInfixOf "SKIP ") (lines full)) `shouldBe` 5
      filter (\l -> any (`isInfixOf` l) ["PASS ", "SKIP "]) (lines out) `shouldBe` []
      last (lines out) `shouldBe` "1 passed, 0 failed, 0 unsupported, 0 engine-error, 5 skipped"
      dropWhile (/= "by dialect:") (lines out) `shouldBe` dropWhile (/= "by dialect:") (lines full)
      (code', out', _) <- stref (canned ++ ["--only-failures"])
      code' `shouldBe` ExitFailure 1
      filter (isInfixOf "FAIL ") (lines out') `shouldSatisfy` ((== 5) . length)
    it "--verbose shows, for a case an external engine failed, the request it was sent and its answer" $ do
      (_, requestLine, _) <- stref ["request", fixtureCorpus </> "mastertool-xe" </> "calls" </> "three-calls.st"]
      (_, out, _) <- stref (canned ++ ["--verbose"])
      let block = takeWhile (\l -> "  " `isPrefixOf` l) (drop 1 (dropWhile (not . isInfixOf "FAIL mastertool-xe/calls/three-calls:") (lines out)))
      drop 2 block
        `shouldBe` [ "  request: " ++ concat (lines requestLine)
                   , "  answer: {\"verdict\": \"ok\", \"operands\": {\"%M0012\": 32767, \"%M13.0\": true}, \"outputs\": {\"OUTPUT1\": true}, \"error\": null}"
                   ]
      (_, quiet, _) <- stref canned
      filter (isInfixOf "  request: ") (lines quiet) `shouldBe` []
    it "keeps the first difference in the JSON report's difference and lists all in differences" $ do
      (_, out, _) <- stref (canned ++ ["--format", "json"])
      let threeCalls = decode (BL.pack out) >>= field ["cases"] >>= \case
            Array cs -> V.find (\c -> field ["id"] c == Just (String "mastertool-xe/calls/three-calls")) cs
            _ -> Nothing
          difference what expected actual = Object (KM.fromList [("what", String what), ("expected", String expected), ("actual", String actual)])
      (threeCalls >>= field ["difference"]) `shouldBe` Just (difference "%M0101" "2" "not reported")
      (threeCalls >>= field ["differences"]) `shouldBe` Just (Array (V.fromList [difference "%M0101" "2" "not reported", difference "OUTPUT1" "false" "true"]))

    it "puts the description, the file, the rules and every difference in JUnit's failure element" $ do
      (_, out, _) <- stref (canned ++ ["--format", "junit"])
      let element = takeWhile (not . isInfixOf "</failure>") (dropWhile (not . isInfixOf "<testcase name=\"three-calls\"") (lines out))
      element `shouldSatisfy` any (isInfixOf "<failure message=\"%M0101: expected 2, got not reported\">description: three module calls with inputs and operand writes between them")
      element `shouldContain` ["file: " ++ fixtureCorpus </> "mastertool-xe" </> "calls" </> "three-calls.st", "rule MT-EXEC-9: a module call runs the program once", "%M0101: expected 2, got not reported"]
      out `shouldSatisfy` isInfixOf "OUTPUT1: expected false, got true</failure>"
    it "does not report the cases outside a shard, not even as skipped" $ do
      (code, out, _) <- stref ["conformance", fixtureCorpus, "--shard", "2/3", "--verbose"]
      code `shouldBe` ExitSuccess
      filter (\l -> any (`isInfixOf` l) ["PASS ", "SKIP "]) (lines out) `shouldBe` ["PASS mastertool-xe/arith/real-rounding", "PASS mastertool-xe/calls/named-vars"]
      last (lines out) `shouldBe` "2 passed, 0 failed, 0 unsupported, 0 engine-error, 0 skipped"
      (_, xml, _) <- stref ["conformance", fixtureCorpus, "--shard", "2/3", "--format", "junit"]
      length (filter (isInfixOf "<testcase ") (lines xml)) `shouldBe` 2
    it "counts a malformed case under its own area directory" $ do
      (code, out, _) <- stref ["conformance", "test" </> "fixtures" </> "malformed", "--format", "json"]
      code `shouldBe` ExitFailure 1
      let areas = decode (BL.pack out) >>= field ["by_area"] >>= \case
            Object o -> Just (map Key.toString (KM.keys o))
            _ -> Nothing
      areas `shouldBe` Just ["mastertool-xe/bad"]
      (_, xml, _) <- stref ["conformance", "test" </> "fixtures" </> "malformed", "--format", "junit"]
      xml `shouldSatisfy` isInfixOf "<testsuite name=\"mastertool-xe/bad\""

  describe "request: the request the runner sends for one case" $ do
    let saturates = fixtureCorpus </> "mastertool-xe" </> "arith" </> "int-add-saturates.st"
    it "prints it on one line, under the case's dialect preset and the --policy given" $ do
      (code, out, err) <- stref ["request", saturates]
      (code, err) `shouldBe` (ExitSuccess, "")
      length (lines out) `shouldBe` 1
      let j = decode (BL.pack out) :: Maybe Value
      (j >>= field ["case"]) `shouldBe` Just (String "mastertool-xe/arith/int-add-saturates")
      (j >>= field ["policies", "overflow"]) `shouldBe` Just (String "saturate")
      (j >>= field ["plc", "init", "%M0010"]) `shouldBe` Just (Number 15000)
      (_, wrapped, _) <- stref ["request", saturates, "--policy", "overflow=wrap"]
      (decode (BL.pack wrapped) >>= field ["policies", "overflow"]) `shouldBe` Just (String "wrap")
    it "is what `stref engine` answers: 15000 + 25000 saturates to 32767 (MT-OP-6)" $ do
      bin <- strefBinary
      (_, rq, _) <- stref ["request", saturates]
      (code, answer, _) <- readProcessWithExitCode bin ["engine"] rq
      code `shouldBe` ExitSuccess
      (decode (BL.pack answer) >>= field ["operands", "%M0012"]) `shouldBe` Just (Number 32767)
    it "names a malformed case's file and line, exit 1; a missing file, a directory or an unknown preset, exit 2" $ do
      (code, out, err) <- stref ["request", "test" </> "fixtures" </> "malformed" </> "mastertool-xe" </> "bad" </> "bad-policy.st"]
      (code, out) `shouldBe` (ExitFailure 1, "")
      err `shouldSatisfy` isInfixOf "bad-policy.st:6: expect-if[0].when.overflow"
      (code2, _, err2) <- stref ["request", "no-such-case.st"]
      code2 `shouldBe` ExitFailure 2
      err2 `shouldSatisfy` isInfixOf "no such file: no-such-case.st"
      (code3, _, err3) <- stref ["request", fixtureCorpus]
      code3 `shouldBe` ExitFailure 2
      err3 `shouldSatisfy` isInfixOf "is a directory"
      (code4, _, err4) <- stref ["request", saturates, "--preset", "nope"]
      code4 `shouldBe` ExitFailure 2
      err4 `shouldSatisfy` isInfixOf "unknown preset 'nope'"

  describe "conformance: an engine that cannot be started stops the run" $ do
    it "a command the shell does not find (status 127): one message, exit 2" $ do
      (code, out, err) <- stref ["conformance", fixtureCorpus, "--engine", "no-such-engine-for-stref --serve"]
      code `shouldBe` ExitFailure 2
      out `shouldBe` ""
      lines err `shouldSatisfy` ((== 1) . length)
      err `shouldSatisfy` isInfixOf "the engine cannot be started: the first 3 cases ended with: the engine exited with status 127"
      err `shouldSatisfy` isInfixOf "no-such-engine-for-stref: not found"
    it "a script that does not exist (the same 'No such file' on every case): one message, exit 2" $ do
      (code, _, err) <- stref ["conformance", fixtureCorpus, "--engine", "sh test/engines/no-such-script.sh", "-j", "2"]
      code `shouldBe` ExitFailure 2
      lines err `shouldSatisfy` ((== 1) . length)
      err `shouldSatisfy` isInfixOf "no-such-script.sh: No such file"
    it "a single case is enough to tell" $ do
      (code, _, err) <- stref ["conformance", fixtureCorpus </> "mastertool-xe" </> "calls" </> "three-calls.st", "--engine", "no-such-engine-for-stref"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` isInfixOf "the engine cannot be started: the only case run ended with"
    it "an engine that starts and then fails on every case is still reported case by case, exit 1" $ do
      (code, out, _) <- stref ["conformance", fixtureCorpus, "--engine", engineScript "crash"]
      code `shouldBe` ExitFailure 1
      last (lines out) `shouldBe` "0 passed, 0 failed, 0 unsupported, 6 engine-error, 0 skipped"

  describe "an engine that is not installed" $ do
    it "conformance --engine matiec and the adapter say where stref looked, an unknown adapter is named: exit 2" $ do
      bin <- strefBinary
      env <- getEnvironment
      let without = [(k, v) | (k, v) <- env, k `notElem` ["STREF_MATIEC", "STREF_IRONPLC", "PATH"]] ++ [("STREF_MATIEC", "/nonexistent/matiec"), ("PATH", "/nonexistent")]
          runWith args = readCreateProcessWithExitCode ((proc bin args) {env = Just without}) ""
      (code, _, err) <- runWith ["conformance", "test" </> "engines" </> "matiec" </> "values.st", "--engine", "matiec"]
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` isInfixOf "/nonexistent/matiec"
      (code2, _, err2) <- runWith ["adapter", "matiec", "--check"]
      code2 `shouldBe` ExitFailure 2
      err2 `shouldSatisfy` isInfixOf "STREF_MATIEC"
      (code3, _, err3) <- runWith ["adapter", "no-such-engine"]
      code3 `shouldBe` ExitFailure 2
      err3 `shouldSatisfy` isInfixOf "no adapter for 'no-such-engine'"
      (code4, _, err4) <- runWith ["adapter", "ironplc", "--check"]
      code4 `shouldBe` ExitFailure 2
      err4 `shouldSatisfy` isInfixOf "STREF_IRONPLC"
  describe "the last line of defence (exit 3)" $ do
    -- a sum of 20,000 ones is a left spine 20,000 levels deep: accepted,
    -- and its value is 20000 (no overflow on INT); with a stack of 100 KB
    -- the runtime system throws a stack overflow, which main turns into
    -- exit 3 with the advice of docs/robustness.md
    let sumOfOnes = intercalate "+" (replicate 20000 "1")
    it "evaluates the deep sum with the default stack" $ do
      (code, out, _) <- stref ["eval", "--", sumOfOnes]
      code `shouldBe` ExitSuccess
      lines out `shouldContain` ["value = 20000 : INT"]
    it "exits 3 with one line on stderr when the stack runs out" $ do
      (code, out, err) <- stref ["+RTS", "-K100k", "-RTS", "eval", "--", sumOfOnes]
      code `shouldBe` ExitFailure 3
      out `shouldBe` ""
      err `shouldBe` "stref: the input is too large or too deeply nested for the stack; raise the limit with +RTS -K<size> -RTS (e.g. -K2g)\n"
