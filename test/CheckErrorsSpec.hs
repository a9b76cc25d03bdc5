-- | Every verification error kind of the checker (catalogue §10, Table 5-1):
-- a rejected example, mostly the catalogue's suggested trigger, and a close
-- twin that is accepted.
module CheckErrorsSpec (spec) where

import Control.Monad (forM_)
import Data.Containers.ListUtils (nubOrd)
import qualified Data.Text.IO as TIO
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Check (checkModule)
import Stref.Checked (ModuleKind (..))
import Stref.Syntax (Module (..), Program (..), VarBlock (..), VarSection (..))
import Stref.Syntax.Parser (parseModule)
import Stref.Policy
import Stref.Syntax (Pos (..))
import Stref.Verification (VerificationError (..))
import Support.Check
import Test.Hspec

-- | (kind, what, rejected module, accepted twin)
data Case = Case Text String Text Text

-- | Declarations used by most cases.
vars :: Text
vars =
  "I, J, Y : INT; D : DINT; U : USINT; W : WORD; BY1 : BYTE; R : REAL; B, B1, B2 : BOOL;\n\
  \V : ARRAY[1..10] OF INT; X : INT; A : BOOL;"

p :: Text -> Text
p = program vars

-- | A one-parameter function F and a two-parameter function G, then the program.
withFuns :: Text -> Text
withFuns body =
  programF
    "FUNCTION F : INT\nVAR_INPUT A : INT; END_VAR\nF := A;\nEND_FUNCTION\n\
    \FUNCTION G : INT\nVAR_INPUT A, C : INT; END_VAR\nG := A + C;\nEND_FUNCTION"
    vars
    body

func :: Text -> Text -> Text
func decls body = "FUNCTION F : INT\n" <> decls <> "\n" <> body <> "\nEND_FUNCTION\n" <> program "Y : INT;" "Y := F(1);"

cases :: [Case]
cases =
  [ -- MT-VERR-7, MT-SCOPE-4, MT-LEX-5
    Case "duplicate-identifier" "same name in one scope, other case" (program "X : INT; x : DINT;" ";") (program "X : INT; X2 : DINT;" ";")
  , Case "duplicate-identifier" "function parameter named like the function" (func "VAR_INPUT F : INT; END_VAR" "F := 1;") (func "VAR_INPUT A : INT; END_VAR" "F := 1;")
  , Case "duplicate-identifier" "program named like a function (MT-POU-13)" ("FUNCTION P : INT\nVAR_INPUT A : INT; END_VAR\nP := A;\nEND_FUNCTION\n" <> program "Y : INT;" ";") ("FUNCTION Q : INT\nVAR_INPUT A : INT; END_VAR\nQ := A;\nEND_FUNCTION\n" <> program "Y : INT;" ";")
  , -- MT-VERR-8, MT-VAR-1
    Case "undeclared-variable" "Y := Z" (p "Y := Z;") (p "Y := X;")
  , -- MT-VERR-9
    Case "undeclared-array" "Y := VV[1]" (p "Y := VV[1];") (p "Y := V[1];")
  , -- MT-VERR-10, MT-OP-21
    Case "undeclared-function" "ABS is not built in" (p "Y := ABS(X);") (withFuns "Y := F(X);")
  , Case "undeclared-function" "called before its declaration (MT-POU-11)"
      ("FUNCTION F1 : INT\nVAR_INPUT A : INT; END_VAR\nF1 := F2(A);\nEND_FUNCTION\nFUNCTION F2 : INT\nVAR_INPUT A : INT; END_VAR\nF2 := A;\nEND_FUNCTION\n" <> program "Y : INT;" "Y := F1(1);")
      ("FUNCTION F2 : INT\nVAR_INPUT A : INT; END_VAR\nF2 := A;\nEND_FUNCTION\nFUNCTION F1 : INT\nVAR_INPUT A : INT; END_VAR\nF1 := F2(A);\nEND_FUNCTION\n" <> program "Y : INT;" "Y := F1(1);")
  , Case "undeclared-function" "REAL_TO_BYTE does not exist (A8)" (p "BY1 := REAL_TO_BYTE(R);") (p "BY1 := ANY_TO_BYTE(R);")
  , -- MT-VERR-11, MT-STMT-9, A16
    Case "integer-expression-expected" "REAL selector" (p "CASE R OF 1: X := 1; END_CASE;") (p "CASE I OF 1: X := 1; END_CASE;")
  , Case "integer-expression-expected" "BYTE selector (A16)" (p "CASE BY1 OF 1: X := 1; END_CASE;") (p "CASE U OF 1: X := 1; END_CASE;")
  , Case "integer-expression-expected" "REAL index" (p "Y := V[R];") (p "Y := V[D];")
  , -- MT-VERR-12, MT-CONV-12
    Case "impossible-conversion" "I := W (WORD to INT)" (p "I := W;") (p "I := WORD_TO_INT(W);")
  , Case "impossible-conversion" "R := D (DINT to REAL)" (p "R := D;") (p "R := I;")
  , Case "impossible-conversion" "R := U (USINT to REAL, not transitive)" (p "R := U;") (p "D := U;")
  , Case "impossible-conversion" "I := 1.5 (MT-CONST-3)" (p "I := 1.5;") (p "R := 1.5;")
  , Case "impossible-conversion" "I + 1.5 (MT-CONST-3)" (p "R := I + 1.5;") (p "R := R + 1.5;")
  , Case "impossible-conversion" "INT condition (MT-STMT-7)" (p "IF I THEN X := 1; END_IF;") (p "IF B THEN X := 1; END_IF;")
  , Case "impossible-conversion" "argument of the wrong type" (withFuns "Y := F(D);") (withFuns "Y := F(U);")
  , -- MT-VERR-13, MT-OP-4, MT-OP-11, MT-OP-15, A15
    Case "invalid-binary-operation" "REAL + DINT" (p "R := R + D;") (p "R := R + I;")
  , Case "invalid-binary-operation" "INT AND INT" (p "X := I AND J;") (p "W := W AND W;")
  , Case "invalid-binary-operation" "BOOL < BOOL" (p "B := B1 < B2;") (p "B := B1 = B2;")
  , Case "invalid-binary-operation" "WORD + WORD" (p "W := W + W;") (p "I := I + J;")
  , Case "invalid-binary-operation" "REAL MOD REAL" (p "R := R MOD R;") (p "D := D MOD D;")
  , Case "invalid-binary-operation" "EXPT with a WORD base" (p "W := EXPT(W, 2);") (p "I := EXPT(I, 2);")
  , -- MT-VERR-14, MT-OP-5
    Case "invalid-unary-operation" "-U" (p "U := -U;") (p "I := -I;")
  , Case "invalid-unary-operation" "NOT I" (p "I := NOT I;") (p "W := NOT W;")
  , Case "invalid-unary-operation" "-W" (p "W := -W;") (p "D := -D;")
  , -- MT-VERR-15
    Case "exit-outside-loop" "EXIT in an IF" (p "IF A THEN EXIT; END_IF;") (p "WHILE A DO IF A THEN EXIT; END_IF; END_WHILE;")
  , -- MT-VERR-16, MT-STMT-22
    Case "unreachable-code" "after RETURN" (p "RETURN; X := 1;") (p "IF A THEN RETURN; END_IF; X := 1;")
  , Case "unreachable-code" "after EXIT" (p "WHILE A DO EXIT; X := 1; END_WHILE;") (p "WHILE A DO X := 1; EXIT; END_WHILE;")
  , -- MT-VERR-17, MT-POU-8
    Case "recursive-call" "F := F(A)" (func "VAR_INPUT A : INT; END_VAR" "F := F(A);") (func "VAR_INPUT A : INT; END_VAR" "F := A;")
  , -- MT-VERR-18, MT-POU-4
    Case "missing-return-value" "IF without ELSE" (func "VAR_INPUT A : INT; END_VAR" "IF A > 0 THEN F := 1; END_IF;") (func "VAR_INPUT A : INT; END_VAR" "IF A > 0 THEN F := 1; ELSE F := 0; END_IF;")
  , Case "missing-return-value" "CASE without ELSE" (func "VAR_INPUT A : INT; END_VAR" "CASE A OF 1: F := 1; END_CASE;") (func "VAR_INPUT A : INT; END_VAR" "CASE A OF 1: F := 1; ELSE F := 2; END_CASE;")
  , Case "missing-return-value" "WHILE may run zero times; REPEAT runs once" (func "VAR_INPUT A : INT; END_VAR" "WHILE A > 0 DO F := 1; A := A - 1; END_WHILE;") (func "VAR_INPUT A : INT; END_VAR\nVAR K : INT; END_VAR" "REPEAT F := 1; K := K + 1; UNTIL K > A END_REPEAT;")
  , Case "missing-return-value" "FOR may run zero times" (func "VAR_INPUT A : INT; END_VAR\nVAR K : INT; END_VAR" "FOR K := 1 TO A DO F := K; END_FOR;") (func "VAR_INPUT A : INT; END_VAR\nVAR K : INT; END_VAR" "F := 0; FOR K := 1 TO A DO F := K; END_FOR;")
  , Case "missing-return-value" "RETURN before the assignment" (func "VAR_INPUT A : INT; END_VAR" "IF A > 0 THEN RETURN; END_IF; F := 1;") (func "VAR_INPUT A : INT; END_VAR" "F := 0; IF A > 0 THEN RETURN; END_IF; F := 1;")
  , Case "missing-return-value" "EXIT before the assignment in REPEAT" (func "VAR_INPUT A : INT; END_VAR" "REPEAT IF A > 0 THEN EXIT; END_IF; F := 1; UNTIL TRUE END_REPEAT;") (func "VAR_INPUT A : INT; END_VAR" "REPEAT F := 1; IF A > 0 THEN EXIT; END_IF; UNTIL TRUE END_REPEAT;")
  , -- MT-VERR-19, MT-VERR-20
    Case "too-many-arguments" "F(1, 2)" (withFuns "Y := F(1, 2);") (withFuns "Y := G(1, 2);")
  , Case "too-few-arguments" "G(1)" (withFuns "Y := G(1);") (withFuns "Y := F(1);")
  , Case "too-few-arguments" "EXPT(I)" (p "I := EXPT(I);") (p "I := EXPT(I, 2);")
  , -- MT-VERR-21
    Case "not-a-function" "X(1) with X : INT" (p "Y := X(1);") (withFuns "Y := F(1);")
  , -- MT-VERR-22
    Case "not-an-array" "X[1] with X : INT" (p "Y := X[1];") (p "Y := V[1];")
  , -- MT-VERR-23
    Case "not-a-variable" "Y := F in the program" (withFuns "Y := F;") (withFuns "Y := F(0);")
  , Case "not-a-variable" "F := 1 in the program" (withFuns "F := 1;") (withFuns "F(1);")
  , -- MT-VERR-24
    Case "not-a-constant" "CASE label that is a plain VAR" (p "CASE X OF Y: X := 1; END_CASE;") ("VAR CONSTANT K : INT := 4; END_VAR\n" <> p "CASE X OF K: X := 1; END_CASE;")
  , Case "not-a-constant" "array bound that is a plain VAR" ("VAR N : INT := 4; END_VAR\n" <> program "Z : ARRAY[1..N] OF INT;" ";") ("VAR CONSTANT N : INT := 4; END_VAR\n" <> program "Z : ARRAY[1..N] OF INT;" "Z[4] := 1;")
  , Case "not-a-constant" "initialiser from a plain VAR" (program "X : INT := 1; Y : INT := X;" ";") ("VAR CONSTANT X : INT := 1; END_VAR\n" <> program "Y : INT := X;" ";")
  , -- MT-VERR-25
    Case "read-not-allowed" "B := OUTPUT1" (p "B := OUTPUT1;") (p "OUTPUT1 := B;")
  , Case "read-not-allowed" "reading a VAR_OUTPUT" ("PROGRAM P\nVAR_OUTPUT O : INT; END_VAR\nVAR X : INT; END_VAR\nX := O;\nEND_PROGRAM\n") ("PROGRAM P\nVAR_OUTPUT O : INT; END_VAR\nVAR X : INT; END_VAR\nO := X;\nEND_PROGRAM\n")
  , -- MT-VERR-26, MT-VERR-47
    Case "write-not-allowed" "INPUT1 := TRUE" (p "INPUT1 := TRUE;") (p "B := INPUT1;")
  , Case "write-not-allowed" "INTERNAL_OVERFLOW := FALSE" (p "INTERNAL_OVERFLOW := FALSE;") (p "B := INTERNAL_OVERFLOW;")
  , Case "write-not-allowed" "writing a VAR CONSTANT" ("VAR CONSTANT K : INT := 1; END_VAR\n" <> p "K := 2;") ("VAR CONSTANT K : INT := 1; END_VAR\n" <> p "X := K;")
  , Case "write-not-allowed" "writing a VAR_INPUT" (func "VAR_INPUT A : INT; END_VAR" "A := 2; F := A;") (func "VAR_INPUT A : INT; END_VAR\nVAR L : INT; END_VAR" "L := 2; F := A + L;")
  , -- MT-VERR-27, MT-STMT-10
    Case "case-value-duplicated" "1 twice" (p "CASE X OF 1: Y := 1; 0, 1: Y := 2; END_CASE;") (p "CASE X OF 1: Y := 1; 0, 2: Y := 2; END_CASE;")
  , Case "case-value-duplicated" "a value inside a range" (p "CASE X OF 1..5: Y := 1; 3: Y := 2; END_CASE;") (p "CASE X OF 1..5: Y := 1; 6: Y := 2; END_CASE;")
  , -- MT-VERR-28
    Case "for-variable-mapped" "mapped control variable" (program "K AT %M0010 : INT; T : INT;" "FOR K := 1 TO 3 DO T := K; END_FOR;") (program "K : INT; T : INT;" "FOR K := 1 TO 3 DO T := K; END_FOR;")
  , -- MT-VERR-29, MT-STMT-20
    Case "for-variable-written" "I := 5 in the body" (p "FOR I := 1 TO 3 DO I := 5; END_FOR;") (p "FOR I := 1 TO 3 DO J := I; END_FOR;")
  , Case "for-variable-written" "nested FOR with the same variable" (p "FOR I := 1 TO 3 DO FOR I := 1 TO 2 DO J := I; END_FOR; END_FOR;") (p "FOR I := 1 TO 3 DO FOR J := 1 TO 2 DO Y := I; END_FOR; END_FOR;")
  , -- MT-VERR-30, MT-ARR-7
    Case "wrong-initializer-count" "too few values" (program "Z : ARRAY[1..3] OF INT := [1, 2];" ";") (program "Z : ARRAY[1..3] OF INT := [1, 2, 3];" ";")
  , Case "wrong-initializer-count" "too many values" (program "Z : ARRAY[1..3] OF INT := [1, 2, 3, 4];" ";") (program "Z : ARRAY[0..3] OF INT := [1, 2, 3, 4];" ";")
  , -- MT-VERR-31, MT-MAP-5, MT-MAP-11
    Case "incompatible-operand" "REAL on %M" (program "Z AT %M0010 : REAL;" ";") (program "Z AT %M0010 : INT;" ";")
  , Case "incompatible-operand" "INT on %F" (program "Z AT %F0001 : INT;" ";") (program "Z AT %F0001 : REAL;" ";")
  , Case "incompatible-operand" "mapped BOOL array" (program "Z AT %M0010 : ARRAY[1..4] OF BOOL;" ";") (program "Z AT %M0010 : ARRAY[1..4] OF WORD;" ";")
  , Case "incompatible-operand" "BOOL on a whole %M" (program "Z AT %M0010 : BOOL;" ";") (program "Z AT %M0010.3 : BOOL;" ";")
  , -- MT-VERR-32, MT-POU-6, MT-PARAM-8
    Case "invalid-parameter-type" "array parameter of a function" (func "VAR_INPUT A : ARRAY[1..3] OF INT; END_VAR" "F := 1;") (func "VAR_INPUT A : INT; END_VAR" "F := 1;")
  , Case "invalid-parameter-type" "BOOL parameter of the program" ("PROGRAM P\nVAR_INPUT A : BOOL; END_VAR\n;\nEND_PROGRAM\n") ("PROGRAM P\nVAR_INPUT A : BYTE; END_VAR\n;\nEND_PROGRAM\n")
  , Case "invalid-parameter-type" "BOOL array parameter of the program" ("PROGRAM P\nVAR_OUTPUT A : ARRAY[1..3] OF BOOL; END_VAR\n;\nEND_PROGRAM\n") ("PROGRAM P\nVAR_OUTPUT A : ARRAY[1..3] OF INT; END_VAR\n;\nEND_PROGRAM\n")
  , -- MT-VERR-33, MT-VERR-34, MT-PARAM-1
    Case "too-many-inputs" "6 VAR_INPUT + 5 VAR_IN_OUT" (params 6 5 0) (params 5 5 0)
  , Case "too-many-outputs" "11 VAR_OUTPUT" (params 1 0 11) (params 1 0 10)
  , -- MT-VERR-36, MT-POU-7
    Case "function-parameter-kind" "VAR_OUTPUT in a function" (func "VAR_INPUT A : INT; END_VAR\nVAR_OUTPUT O : INT; END_VAR" "F := A;") (func "VAR_INPUT A : INT; END_VAR\nVAR O : INT; END_VAR" "F := A;")
  , Case "function-parameter-kind" "VAR_IN_OUT in a function" (func "VAR_INPUT A : INT; END_VAR\nVAR_IN_OUT O : INT; END_VAR" "F := A;") (func "VAR_INPUT A : INT; END_VAR\nVAR CONSTANT O : INT := 1; END_VAR" "F := A + O;")
  , -- MT-VERR-37, MT-CONST-5, A12, MT-ARR-4
    Case "value-out-of-limits" "U : USINT := 256" (program "Z : USINT := 256;" ";") (program "Z : USINT := 255;" ";")
  , Case "value-out-of-limits" "I : INT := 16#8000 (MT-CONST-6)" (program "Z : INT := 16#8000;" ";") (program "Z : INT := -32768;" ";")
  , Case "value-out-of-limits" "ARRAY[-1..5]" (program "Z : ARRAY[-1..5] OF INT;" ";") (program "Z : ARRAY[0..5] OF INT;" ";")
  , Case "value-out-of-limits" "CASE label outside the selector's type" (p "CASE U OF 256: X := 1; END_CASE;") (p "CASE U OF 255: X := 1; END_CASE;")
  , Case "value-out-of-limits" "B := 2 (MT-LEX-16)" (p "B := 2;") (p "B := 1;")
  , -- MT-VERR-38
    Case "min-greater-than-max" "ARRAY[5..1]" (program "Z : ARRAY[5..1] OF INT;" ";") (program "Z : ARRAY[1..5] OF INT;" ";")
  , Case "min-greater-than-max" "CASE 10..5" (p "CASE X OF 10..5: Y := 1; END_CASE;") (p "CASE X OF 5..10: Y := 1; END_CASE;")
  , -- MT-VERR-39, MT-MAP-2, MT-MAP-6
    Case "invalid-operand" "%D0001" (program "Z AT %D0001 : INT;" ";") (program "Z AT %M0001 : INT;" ";")
  , Case "invalid-operand" "%M0001.16" (program "Z AT %M0001.16 : BOOL;" ";") (program "Z AT %M0001.15 : BOOL;" ";")
  , Case "invalid-operand" "%TM without its position (MT-MAP-9)" (program "Z AT %TM0010 : ARRAY[1..4] OF INT;" ";") (program "Z AT %TM0010[0] : ARRAY[1..4] OF INT;" ";")
  , -- MT-VERR-43, MT-LIM-3, A26: 2000 INT = 4000 bytes; 1536 INT = 3072 bytes
    Case "data-area-exceeded" "ARRAY[1..2000] OF INT" (program "Z : ARRAY[1..2000] OF INT;" ";") (program "Z : ARRAY[1..1536] OF INT;" ";")
  , Case "data-area-exceeded" "globals and locals together" ("VAR G : ARRAY[1..1000] OF INT; END_VAR\n" <> program "Z : ARRAY[1..537] OF INT;" ";") ("VAR G : ARRAY[1..1000] OF INT; END_VAR\n" <> program "Z : ARRAY[1..536] OF INT; M AT %M0000 : ARRAY[1..100] OF INT;" ";")
  , -- MT-VERR-44
    Case "invalid-array-size" "more elements than operand addresses" (program "Z AT %M0000 : ARRAY[0..65536] OF INT;" ";") (program "Z AT %M0000 : ARRAY[0..65535] OF INT;" ";")
  , -- A22
    Case "whole-array-use" "Z := V" (program "Z, V : ARRAY[1..3] OF INT;" "Z := V;") (program "Z, V : ARRAY[1..3] OF INT;" "Z[1] := V[1];")
  , Case "whole-array-use" "an array as an operand" (program "Z : ARRAY[1..3] OF INT; X : INT;" "X := Z + 1;") (program "Z : ARRAY[1..3] OF INT; X : INT;" "X := Z[1] + 1;")
  , -- MT-STMT-16
    Case "invalid-for-variable" "DINT control variable" (p "FOR D := 1 TO 3 DO X := 1; END_FOR;") (p "FOR U := 1 TO 3 DO X := 1; END_FOR;")
  , Case "for-type-mismatch" "USINT end for an INT variable" (p "FOR I := 1 TO U DO X := 1; END_FOR;") (p "FOR I := 1 TO J DO X := 1; END_FOR;")
  , Case "value-out-of-limits" "FOR bound outside the control type" (p "FOR U := 0 TO 300 DO X := 1; END_FOR;") (p "FOR U := 0 TO 255 BY 5 DO X := 1; END_FOR;")
  , -- MT-POU-3
    Case "function-without-input" "no VAR_INPUT" (func "VAR A : INT; END_VAR" "F := A;") (func "VAR_INPUT A : INT; END_VAR" "F := A;")
  , Case "missing-statement" "an empty PROGRAM (MT-POU-12)" "PROGRAM P\nEND_PROGRAM\n" "PROGRAM P\n;\nEND_PROGRAM\n"
  , -- the array initialiser form
    Case "invalid-initializer" "a list for a scalar" (program "Z : INT := [1];" ";") (program "Z : ARRAY[1..1] OF INT := [1];" ";")
  , Case "builtin-call-statement" "EXPT as a statement" (p "EXPT(I, 2);") (p "I := EXPT(I, 2);")
  ]
  where
    params nIn nInOut nOut =
      "PROGRAM P\n"
        <> block "VAR_INPUT" "IN" nIn
        <> block "VAR_IN_OUT" "IO" nInOut
        <> block "VAR_OUTPUT" "OUT" nOut
        <> ";\nEND_PROGRAM\n"
    block :: Text -> Text -> Int -> Text
    block _ _ 0 = ""
    block kw prefix n = kw <> "\n" <> T.concat [prefix <> T.pack (show i) <> " : INT;\n" | i <- [1 .. n]] <> "END_VAR\n"

spec :: Spec
spec = describe "Check: verification errors" $ do
  forM_ cases $ \(Case kind what bad good) -> describe (T.unpack kind) $ do
    it ("rejects " <> what) $ rejects kind bad
    it ("accepts the twin of " <> what) $ accepts good
  describe "procedure-parameters (MT-PARAM-2, MT-VERR-35)" $ do
    let src = "PROGRAM P\nVAR_INPUT A : INT; END_VAR\n;\nEND_PROGRAM\n"
    it "rejects parameters in a P module" $ rejectsWith mastertoolXE ProcedureModule "procedure-parameters" src
    it "accepts them in an F module" $ acceptsWith mastertoolXE FunctionModule src
    it "accepts a P module whose program has only VAR" $ acceptsWith mastertoolXE ProcedureModule (program "A : INT;" "A := 1;")
  describe "rules the parser enforces first, checked on syntax trees" $ do
    let parsed src = either (error . show) id (parseModule mastertoolXE "t.st" src)
        kindsOfTree = either (map veKind) (const []) . checkModule mastertoolXE FunctionModule
    it "rejects a parameter section among the globals (misplaced-parameter-section)" $ do
      let m = parsed ("VAR G : INT; END_VAR\n" <> program "X : INT;" "X := G;")
          m' = m {modGlobals = [b {vbSection = SecInput} | b <- modGlobals m]}
      kindsOfTree m `shouldBe` []
      kindsOfTree m' `shouldContain` ["misplaced-parameter-section"]
    it "rejects AT on a program parameter (mapping-not-allowed)" $ do
      let m = parsed (program "X AT %M0001 : INT;" "X := 1;")
          prog = modProgram m
          m' = m {modProgram = prog {prBlocks = [b {vbSection = SecInOut} | b <- prBlocks prog]}}
      kindsOfTree m `shouldBe` []
      kindsOfTree m' `shouldContain` ["mapping-not-allowed"]
  describe "docs/diagnostics.md" $ do
    sources <- runIO (mapM TIO.readFile ["src/Stref/Check.hs", "src/Stref/Check/Monad.hs", "src/Stref/Check/Expr.hs", "src/Stref/Check/Stmt.hs", "src/Stref/Check/Const.hs"])
    doc <- runIO (TIO.readFile "docs/diagnostics.md")
    let kinds = nubOrd (concatMap reportedKinds sources)
    it "finds the kinds in the checker's source" $ length kinds `shouldSatisfy` (> 40)
    forM_ kinds $ \kind -> it ("documents " <> T.unpack kind) $ doc `shouldSatisfy` T.isInfixOf ("| `" <> kind <> "` |")
  describe "error reporting" $ do
    it "reports several errors, ordered by position" $
      kindsOf (p "Y := Z;\nI := W;\nU := -U;")
        `shouldBe` ["undeclared-variable", "impossible-conversion", "invalid-unary-operation"]
    it "reports an error at the offending name: line 6 (after 5 lines of header), column 6" $
      either (map vePos) (const []) (checkText (p "Y := Z;")) `shouldBe` [Pos 6 6]

-- | Every kind the checker's source can report, read from the source text.
reportedKinds :: T.Text -> [T.Text]
reportedKinds src =
  [ T.takeWhile (/= '"') rest
  | marker <- ["report \"", "verificationError \""]
  , (_, hit) <- T.breakOnAll marker src
  , let rest = T.drop (T.length marker) hit
  ]
