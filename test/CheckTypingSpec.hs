-- | Literal compatibility (Table 4-15), implicit conversion edges
-- (MT-CONV-6) and name resolution (MT-SCOPE-5 and its alternative).
module CheckTypingSpec (spec) where

import Control.Monad (forM_)
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Checked
import Stref.Policy
import Stref.Types
import Stref.Values
import Support.Check
import Test.Hspec

-- | Table 4-15 read per type (catalogue §4, "derived admissible literal
-- range"), with the edges just inside and just outside.
literalEdges :: [(BasicType, [Text], [Text])]
literalEdges =
  [ (USINT, ["0", "255", "16#FF"], ["256", "-1"])
  , (BYTE, ["0", "255", "2#1111_1111"], ["256", "-1"])
  , (INT, ["-32768", "32767", "16#7FFF", "-1_532"], ["32768", "-32769", "16#8000"])
  , (WORD, ["0", "65535", "16#FFFF"], ["65536", "-1"])
  , (DINT, ["-2147483648", "2147483647", "16#8000"], ["2147483648", "-2147483649", "16#FFFF_FFFF"])
  , (DWORD, ["0", "4294967295", "16#FFFF_ffff", "16#980ABE4D"], ["4294967296", "-1"])
  , (BOOL, ["0", "1", "TRUE", "FALSE"], ["2", "-1"])
  , -- an integer constant is a REAL through INT -> REAL only (MT-CONST-4, A10)
    (REAL, ["1.5", "-1.34E-2", "0", "-32768", "32767", "1_254.4879"], ["32768", "-32769", "40000"])
  ]

assignTo :: BasicType -> Text -> Text
assignTo t lit = program ("Z : " <> typeName t <> ";") ("Z := " <> lit <> ";")

-- | The seven implicit edges of MT-CONV-6, written out from the catalogue.
mastertoolEdges :: [(BasicType, BasicType)]
mastertoolEdges =
  [(BYTE, WORD), (BYTE, DWORD), (WORD, DWORD), (USINT, INT), (USINT, DINT), (INT, DINT), (INT, REAL)]

assignVar :: BasicType -> BasicType -> Text
assignVar s t = program ("S : " <> typeName s <> "; T : " <> typeName t <> ";") "T := S;"

spec :: Spec
spec = describe "Check: typing" $ do
  describe "integer literals against Table 4-15 (MT-CONST-1..6)" $
    forM_ literalEdges $ \(t, good, bad) -> do
      forM_ good $ \lit -> it ("accepts " <> T.unpack lit <> " as " <> show t) $ accepts (assignTo t lit)
      forM_ bad $ \lit -> it ("rejects " <> T.unpack lit <> " as " <> show t) $ rejects "value-out-of-limits" (assignTo t lit)

  describe "literals take the type of the other operand or the parameter (MT-CONST-1)" $ do
    it "rejects U + 256 with U : USINT" $ rejects "value-out-of-limits" (program "U : USINT; D : DINT;" "D := U + 256;")
    it "accepts U + 255 with U : USINT" $ accepts (program "U : USINT; D : DINT;" "D := U + 255;")
    it "rejects 40000 passed to an INT parameter" $
      rejects "value-out-of-limits" (programF "FUNCTION F : INT\nVAR_INPUT A : INT; END_VAR\nF := A;\nEND_FUNCTION" "Y : INT;" "Y := F(40000);")
    it "accepts -32768 passed to an INT parameter" $
      accepts (programF "FUNCTION F : INT\nVAR_INPUT A : INT; END_VAR\nF := A;\nEND_FUNCTION" "Y : INT;" "Y := F(-32768);")
    it "accepts an integer literal in a REAL operation (MT-CONST-4)" $ accepts (program "R : REAL;" "R := R * 100;")
    it "rejects a real literal with an INT operand (MT-CONST-3)" $ rejects "impossible-conversion" (program "I : INT; B : BOOL;" "B := I < 1.5;")
    it "types an EXPT exponent literal as USINT: 256 is out of its limits (MT-OP-20)" $
      rejects "value-out-of-limits" (program "I : INT;" "I := EXPT(I, 256);")

  describe "implicit conversions: exactly the seven edges under mastertool (MT-CONV-6, A9)" $
    forM_ [(s, t) | s <- allBasicTypes, t <- allBasicTypes, s /= t] $ \(s, t) ->
      if (s, t) `elem` mastertoolEdges
        then it ("inserts " <> show s <> " -> " <> show t) $ accepts (assignVar s t)
        else it ("refuses " <> show s <> " -> " <> show t) $ rejects "impossible-conversion" (assignVar s t)

  describe "the implicit-conversions policy" $ do
    let iec = mastertoolXE {pImplicitConversions = ImplicitIecWidening}
        codesys = mastertoolXE {pImplicitConversions = ImplicitCodesys}
    it "iec-widening adds USINT -> REAL" $ acceptsWith iec FunctionModule (assignVar USINT REAL)
    it "iec-widening still refuses DINT -> REAL" $ rejectsWith iec FunctionModule "impossible-conversion" (assignVar DINT REAL)
    it "codesys adds BYTE -> INT" $ acceptsWith codesys FunctionModule (assignVar BYTE INT)
    it "codesys also accepts the integer constant 65535 as REAL (through WORD -> REAL)" $
      acceptsWith codesys FunctionModule (assignTo REAL "65535")
    it "codesys still refuses 65536 as REAL (no DINT -> REAL edge)" $
      rejectsWith codesys FunctionModule "value-out-of-limits" (assignTo REAL "65536")
    it "codesys refuses the narrowing INT -> USINT" $ rejectsWith codesys FunctionModule "impossible-conversion" (assignVar INT USINT)

  describe "binary operands meet at a common type (MT-CONV-11 b)" $ do
    it "accepts U + I (USINT -> INT) assigned to a DINT" $ accepts (program "U : USINT; I : INT; D : DINT;" "D := U + I;")
    it "accepts BYTE OR WORD" $ accepts (program "B : BYTE; W : WORD;" "W := B OR W;")
    it "rejects U + R (USINT -> REAL is explicit)" $ rejects "invalid-binary-operation" (program "U : USINT; R : REAL;" "R := U + R;")
    it "rejects W + D (no edge across the families)" $ rejects "invalid-binary-operation" (program "W : WORD; D : DINT;" "D := W + D;")

  describe "name resolution: global-wins (MT-SCOPE-5, A4)" $ do
    let shadow = "VAR G : INT; END_VAR\nPROGRAM P\nVAR G : REAL; END_VAR\n"
    it "accepts a local named like a global" $ accepts (shadow <> "G := 5;\nEND_PROGRAM\n")
    it "resolves the local's uses to the global INT, so G := 1.5 is rejected" $
      rejects "impossible-conversion" (shadow <> "G := 1.5;\nEND_PROGRAM\n")
    it "resolves a function parameter named like a global to the global" $
      accepts "VAR G : INT; END_VAR\nFUNCTION F : INT\nVAR_INPUT G : REAL; END_VAR\nF := G;\nEND_FUNCTION\nPROGRAM P\nVAR Y : INT; END_VAR\nY := F(1.5);\nEND_PROGRAM\n"
    it "still reports two locals with one name" $ rejects "duplicate-identifier" (program "G : INT; G : REAL;" ";")
    it "lets sibling POUs use the same local names (MT-SCOPE-6)" $
      accepts "FUNCTION F : INT\nVAR_INPUT A : INT; END_VAR\nVAR X : INT; END_VAR\nX := A; F := X;\nEND_FUNCTION\nPROGRAM P\nVAR X : INT; END_VAR\nX := F(1);\nEND_PROGRAM\n"

  describe "name resolution: local-wins" $ do
    let lw = mastertoolXE {pNameResolution = LocalWins}
        shadow = "VAR G : INT; END_VAR\nPROGRAM P\nVAR G : REAL; END_VAR\n"
    it "resolves to the local REAL, so G := 1.5 is accepted" $ acceptsWith lw FunctionModule (shadow <> "G := 1.5;\nEND_PROGRAM\n")
    it "resolves a parameter to itself, so F := G (REAL to INT) is rejected" $
      rejectsWith lw FunctionModule "impossible-conversion" "VAR G : INT; END_VAR\nFUNCTION F : INT\nVAR_INPUT G : REAL; END_VAR\nF := G;\nEND_FUNCTION\nPROGRAM P\nVAR Y : INT; END_VAR\nY := F(1.5);\nEND_PROGRAM\n"

  describe "identifiers: case-insensitive, 32 significant characters (MT-LEX-4, MT-LEX-5)" $ do
    -- both names share their first 32 characters ABCDEFGHIJABCDEFGHIJABCDEFGHIJAB
    let longNames = program "ABCDEFGHIJABCDEFGHIJABCDEFGHIJAB_1 : INT; ABCDEFGHIJABCDEFGHIJABCDEFGHIJAB_2 : INT;" ";"
    it "treats names equal in their first 32 characters as one" $ rejects "duplicate-identifier" longNames
    it "keeps them apart with identifier-length=unlimited" $ acceptsWith mastertoolXE {pIdentifierLength = Unlimited} FunctionModule longNames
    it "uses a name in another letter case" $ accepts (program "Nivel_Vaso1 : INT;" "nivel_vaso1 := 1; NIVEL_VASO1 := Nivel_vaso1;")

  describe "signals (MT-SIG-1, A20, MT-SCOPE-9)" $ do
    it "does not show INPUT1 inside a function" $
      rejects "undeclared-variable" "FUNCTION F : BOOL\nVAR_INPUT A : INT; END_VAR\nF := INPUT1;\nEND_FUNCTION\nPROGRAM P\nVAR B : BOOL; END_VAR\nB := F(1);\nEND_PROGRAM\n"
    it "shows INTERNAL_OVERFLOW inside a function" $
      accepts "FUNCTION F : BOOL\nVAR_INPUT A : INT; END_VAR\nF := INTERNAL_OVERFLOW;\nEND_FUNCTION\nPROGRAM P\nVAR B : BOOL; END_VAR\nB := F(1);\nEND_PROGRAM\n"
    it "accepts the manual's use of signals in the program" $
      accepts (program "B : BOOL;" "IF INTERNAL_OVERFLOW THEN OUTPUT1 := FALSE; ELSE OUTPUT1 := TRUE; END_IF; B := INPUT2;")

  describe "literal values in the checked program" $ do
    let valueOf t lit = do
          m <- elaborate (assignTo t lit)
          pure [v | SAssign _ _ (CLit v) <- cpBody (cmProgram m)]
    it "reads the integer constant -32768 as the REAL -32768.0 (A10)" $ valueOf REAL "-32768" `shouldReturn` [VReal (-32768)]
    it "rounds 0.1 to the binary32 16#3DCCCCCD" $ valueOf REAL "0.1" `shouldReturn` [VReal (realFromBits 0x3DCCCCCD)]
    it "rounds 1_254.4879 to 1254.4879150390625 (MT-LEX-14)" $ valueOf REAL "1_254.4879" `shouldReturn` [VReal 1254.4879150390625]
    it "folds -32768 into an INT literal (MT-LEX-19)" $ valueOf INT "-32768" `shouldReturn` [VInt (-32768)]
    it "reads BOOL 1 as TRUE (MT-LEX-16)" $ valueOf BOOL "1" `shouldReturn` [VBool True]
    it "reads 16#FFFF as the WORD 16#FFFF" $ valueOf WORD "16#FFFF" `shouldReturn` [VWord 65535]
