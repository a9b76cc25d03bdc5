{-# LANGUAGE ScopedTypeVariables #-}

-- | The nexto dialect: CODESYS V3 as the Nexto manual documents it, on the
-- IEC core. Expected values come from the rules named, worked out by hand.
module IEC.NextoSpec (spec) where

import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.IEC.Engine (Call (..))
import Stref.IEC.Eval (ResetEvent (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Support.Iec
import Test.Hspec
import Test.QuickCheck (property)
import Stref.IEC.Memory (decode, encode, layout)
import Stref.Conformance.Protocol (Scalar (..))

spec :: Spec
spec = describe "the nexto dialect" $ do
  describe "the standard library (policy standard-library)" $ do
    it "codesys: SR takes SET1 and RESET, and the counters count in WORD (NX-FB-1, NX-FB-11)" $ do
      runMain nexto "VAR b : SR; END_VAR b(SET1 := TRUE, RESET := FALSE);" 1 "b.Q1" `shouldBe` Right (VBool True)
      runMain nexto "VAR c : CTU; END_VAR c(CU := TRUE, RESET := FALSE, PV := 1);" 1 "c.CV" `shouldBe` Right (VInt WORD 1)
    it "codesys: CTD does not count below 0 (a WORD)" $
      runMain nexto "VAR c : CTD; cnt : INT; END_VAR cnt := cnt + 1; c(CD := cnt MOD 2 = 1, LOAD := cnt = 1, PV := 1);" 6 "c.CV" `shouldBe` Right (VInt WORD 0)
    it "iec: SR takes S1 and R, and the counters count in INT (TC-FB-2, TC-FB-13)" $ do
      runMain nexto {pStandardLibrary = LibraryIec} "VAR b : SR; END_VAR b(S1 := TRUE, R := FALSE);" 1 "b.Q1" `shouldBe` Right (VBool True)
      runMain nexto {pStandardLibrary = LibraryIec} "VAR c : CTD; END_VAR c(CD := TRUE, LD := FALSE, PV := 1);" 1 "c.CV" `shouldBe` Right (VInt INT (-1))
    it "a program written for one library is rejected under the other" $
      rejectKind tecomat "PROGRAM MAIN\nVAR b : SR; END_VAR\nb(SET1 := TRUE);\nEND_PROGRAM\n" `shouldBe` Just ("unknown-parameter", 3)
  describe "the preset" $ do
    it "wraps on overflow: INT 32767 + 1 = -32768 (NX-OP-32)" $
      runMain nexto "VAR i : INT := 32767; END_VAR i := i + 1;" 1 "i" `shouldBe` Right (VInt INT (-32768))
    it "widens implicitly and rejects narrowing (NX-CONV-2, NX-CONV-3)" $ do
      runMain nexto "VAR i : INT := 7; x : REAL; END_VAR x := i;" 1 "x" `shouldBe` Right (VReal 7)
      rejectKind nexto "PROGRAM MAIN\nVAR i : INT; d : DINT; END_VAR\ni := d;\nEND_PROGRAM\n" `shouldBe` Just ("type-mismatch", 3)
    it "lets a WORD be stored in an INT, as the manual's CTUD example does (NX-CONV-7)" $
      runMain nexto "VAR w : WORD := 16#FFFF; i : INT; END_VAR i := w;" 1 "i" `shouldBe` Right (VInt INT (-1))
  describe "messages cite the rules by the dialect's catalogue" $ do
    let cites pol src = fmap (T.takeWhileEnd (/= '(')) (rejectMessage pol src)
        exitOutside = "PROGRAM MAIN\nEXIT;\nEND_PROGRAM\n"
        hidden = "FUNCTION_BLOCK FB\nVAR h : INT; END_VAR\nh := 1;\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR f : FB; i : INT; END_VAR\ni := f.h;\nEND_PROGRAM\n"
        mixed = "FUNCTION F : INT\nVAR_INPUT a, b : INT; END_VAR\nF := a + b;\nEND_FUNCTION\nPROGRAM MAIN\nVAR i : INT; END_VAR\ni := F(a := 1, 2);\nEND_PROGRAM\n"
        recursive = "FUNCTION F : INT\nVAR_INPUT a : INT; END_VAR\nF := F(a);\nEND_FUNCTION\nPROGRAM MAIN\nEND_PROGRAM\n"
    it "under nexto the NX ids of a rule the Nexto manual states (NX-STMT-38, NX-POU-19, NX-POU-12, NX-POU-50, NX-VAR-9)" $ do
      cites nexto exitOutside `shouldBe` Just "NX-STMT-38)"
      cites nexto hidden `shouldBe` Just "NX-POU-19)"
      cites nexto mixed `shouldBe` Just "NX-POU-12, NX-ERR-30)"
      cites nexto recursive `shouldBe` Just "NX-POU-50)"
      cites nexto "FUNCTION F : INT\nVAR_TEMP t : INT; END_VAR\nF := 1;\nEND_FUNCTION\nPROGRAM MAIN\nEND_PROGRAM\n" `shouldBe` Just "NX-VAR-9)"
    it "under tecomat the TC ids, and under nexto too where the Nexto manual is silent" $ do
      cites tecomat exitOutside `shouldBe` Just "TC-STMT-36)"
      cites tecomat hidden `shouldBe` Just "TC-POU-23)"
      cites tecomat mixed `shouldBe` Just "TC-POU-12)"
      cites tecomat recursive `shouldBe` Just "TC-POU-2)"
      cites nexto "FUNCTION F : INT\nVAR_EXTERNAL g : INT; END_VAR\nF := 1;\nEND_FUNCTION\nPROGRAM MAIN\nEND_PROGRAM\n" `shouldBe` Just "TC-VAR-9..15)"
    it "an X_TO_Y conversion's argument of another type: TC-CONV-6 under tecomat, NX-CONV-10 under nexto" $ do
      let conversion = "PROGRAM MAIN\nVAR ratio : REAL := 1.5; count : INT; END_VAR\ncount := DINT_TO_INT(ratio);\nEND_PROGRAM\n"
      cites tecomat conversion `shouldBe` Just "TC-CONV-6)"
      cites nexto conversion `shouldBe` Just "NX-CONV-10)"
  describe "statements of CODESYS (extensions = codesys)" $ do
    it "JMP goes back to a label: the manual's loop ends with i = 10 (NX-STMT-42, NX-STMT-43)" $
      runMain nexto "VAR i : INT; END_VAR i := 0; label1: i := i + 1; IF i < 10 THEN JMP label1; END_IF" 1 "i" `shouldBe` Right (VInt INT 10)
    it "JMP out of a loop to a label of the enclosing block" $
      runMain nexto "VAR i, j : INT; END_VAR FOR i := 1 TO 10 DO j := i; IF i = 4 THEN JMP done; END_IF END_FOR j := 100; done: ;" 1 "j" `shouldBe` Right (VInt INT 4)
    it "a JMP to a label of a nested block is rejected" $
      rejectKind nexto "PROGRAM MAIN\nVAR i : INT; END_VAR\nJMP inner;\nIF TRUE THEN inner: i := 1; END_IF\nEND_PROGRAM\n" `shouldBe` Just ("undeclared-label", 3)
    it "CONTINUE skips the rest of the body and FOR still counts (NX-STMT-35, NX-STMT-37)" $
      runMain nexto "VAR i, cnt : INT; END_VAR FOR i := 1 TO 5 DO IF i MOD 2 = 0 THEN CONTINUE; END_IF cnt := cnt + 1; END_FOR" 1 "cnt" `shouldBe` Right (VInt INT 3)
    it "CONTINUE outside a loop is rejected" $
      rejectKind nexto "PROGRAM MAIN\nVAR i : INT; END_VAR\nCONTINUE;\nEND_PROGRAM\n" `shouldBe` Just ("continue-outside-loop", 3)
    it "an assignment chain stores in every target (NX-STMT-6)" $ do
      runMain nexto "VAR a, b, c : INT := 1; END_VAR a := b := c + 9;" 1 "a" `shouldBe` Right (VInt INT 10)
      runMain nexto "VAR a, b, c : INT := 1; END_VAR a := b := c + 9;" 1 "b" `shouldBe` Right (VInt INT 10)
    it "the next target takes what the previous one stored: INT := REAL := INT is rejected (NX-STMT-6, NX-CONV-5)" $
      rejectKind nexto "PROGRAM MAIN\nVAR i : INT; x : REAL; END_VAR\ni := x := i;\nEND_PROGRAM\n" `shouldBe` Just ("type-mismatch", 3)
    it "S= sets and keeps, R= resets (NX-STMT-7, NX-STMT-8)" $ do
      runMain nexto "VAR a, b : BOOL; cnt : INT; END_VAR cnt := cnt + 1; b := cnt = 1; a S= b;" 3 "a" `shouldBe` Right (VBool True)
      runMain nexto "VAR a : BOOL := TRUE; END_VAR a R= TRUE;" 1 "a" `shouldBe` Right (VBool False)
    it "in a S= b R= f, both refer to f (NX-STMT-9)" $ do
      runMain nexto "VAR a, b : BOOL := TRUE; f : BOOL := TRUE; END_VAR a := FALSE; a S= b R= f;" 1 "a" `shouldBe` Right (VBool True)
      runMain nexto "VAR a, b : BOOL := TRUE; f : BOOL := TRUE; END_VAR a := FALSE; a S= b R= f;" 1 "b" `shouldBe` Right (VBool False)
    it "END_IF needs no semicolon (NX-STMT-3)" $
      runMain nexto "VAR i : INT; END_VAR IF TRUE THEN i := 1; END_IF i := i + 1;" 1 "i" `shouldBe` Right (VInt INT 2)
    it "under extensions = none, CONTINUE is no statement" $
      rejectKind nexto {pExtensions = ExtensionsNone} "PROGRAM MAIN\nVAR i : INT; END_VAR\nFOR i := 1 TO 2 DO CONTINUE; END_FOR;\nEND_PROGRAM\n" `shouldSatisfy` (/= Nothing)
  describe "methods, properties, actions, EXTENDS (test/fixtures/nexto/methods.st)" $ do
    src <- runIO (TIO.readFile "test/fixtures/nexto/methods.st")
    let at path = runUnit nexto src 1 path
    it "a method calling another method dispatches on the instance's type (NX-POU-31, NX-POU-34)" $ do
      at "MAIN.r1" `shouldBe` Right (VInt INT 1)
      at "MAIN.r2" `shouldBe` Right (VInt INT 2)
    it "SUPER^.m() runs the base's method (NX-POU-46)" $
      at "MAIN.r3" `shouldBe` Right (VInt INT 10)
    it "THIS^.x is the instance's x where an input x hides it (NX-POU-28)" $
      at "MAIN.r4" `shouldBe` Right (VInt INT 8)
    it "a property's SET and GET (NX-POU-38)" $ do
      at "MAIN.b.milli" `shouldBe` Right (VInt DINT 22000)
      at "MAIN.sec" `shouldBe` Right (VInt DINT 22)
    it "an action runs on the instance's variables (NX-POU-41)" $
      at "MAIN.r5" `shouldBe` Right (VInt INT 0)
    it "a derived FB that declares a base variable again is rejected (NX-POU-45)" $
      rejectKind nexto "FUNCTION_BLOCK A\nVAR x : INT; END_VAR\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK B EXTENDS A\nVAR x : INT; END_VAR\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR b : B; END_VAR\nb();\nEND_PROGRAM\n" `shouldBe` Just ("redeclared-inherited", 5)
    it "multiple inheritance is rejected (NX-POU-47)" $
      fmap fst (rejectKind nexto "FUNCTION_BLOCK A\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK C\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK B EXTENDS A, C\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nEND_PROGRAM\n") `shouldBe` Just "multiple-inheritance"
  describe "the language policies, both alternatives (left out of the corpus sweeps)" $ do
    let unit body = "PROGRAM MAIN\n" <> body <> "\nEND_PROGRAM\n"
    it "enumerations: integer values mix with numbers; symbolic ones do not (NX-TYPE-60, TC-TYPE-36)" $ do
      let src = "TYPE COLOR : (red, yellow, green := 10); END_TYPE\nPROGRAM MAIN\nVAR c : COLOR; i : INT; END_VAR\nc := green; i := c + 1;\nEND_PROGRAM\n"
      runUnit nexto src 1 "MAIN.i" `shouldBe` Right (VInt INT 11)
      fmap fst (rejectKind nexto {pEnumerations = EnumSymbolic} src) `shouldBe` Just "type-mismatch"
    it "bit-string-arithmetic: yes wraps BYTE + BYTE, no rejects it (NX-OP-23)" $ do
      runMain nexto "VAR a : BYTE := 250; b : BYTE := 10; END_VAR a := a + b;" 1 "a" `shouldBe` Right (VInt BYTE 4)
      fmap fst (rejectKind nexto {pBitStringArithmetic = BitArithmeticNo} (unit "VAR a : BYTE; END_VAR\na := a + a;")) `shouldBe` Just "invalid-binary-operation"
    it "program-calls: allowed keeps the called program's state; forbidden rejects the call (NX-POU-3, TC-POU-44)" $ do
      let src = "PROGRAM Counter\nVAR_OUTPUT n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\nPROGRAM MAIN\nVAR seen : INT; END_VAR\nCounter(); Counter(); seen := Counter.n;\nEND_PROGRAM\nCONFIGURATION Cfg\nRESOURCE Res ON Plc\nTASK Cyclic(INTERVAL := T#10ms);\nPROGRAM Main WITH Cyclic : MAIN;\nEND_RESOURCE\nEND_CONFIGURATION\n"
      runUnit nexto src 2 "MAIN.seen" `shouldBe` Right (VInt INT 4)
      fmap fst (rejectKind nexto {pProgramCalls = ProgramCallsForbidden} src) `shouldBe` Just "program-call"
    it "fb-access: codesys writes an output from outside; iec rejects it (NX-POU-19, TC-POU-24)" $ do
      let src = "FUNCTION_BLOCK F\nVAR_OUTPUT q : INT; END_VAR\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR f : F; END_VAR\nf.q := 5;\nEND_PROGRAM\n"
      runUnit nexto src 1 "MAIN.f.q" `shouldBe` Right (VInt INT 5)
      rejectKind nexto {pFBAccess = AccessIec} src `shouldBe` Just ("write-not-allowed", 6)
    it "reserved-names: codesys frees the standard FBs' parameter names, iec reserves them (NX-LEX-12, TC-LEX-4)" $ do
      runMain nexto "VAR q : INT; END_VAR q := 3;" 1 "q" `shouldBe` Right (VInt INT 3)
      fmap fst (rejectKind nexto {pReservedNames = ReservedIec} (unit "VAR q : INT; END_VAR\nq := 3;")) `shouldBe` Just "reserved-name"
    it "time-range: unsigned holds T#49d17h2m47s295ms and wraps below 0; signed holds T#-1ms and rejects the larger literal (NX-TYPE-30, TC-TYPE-19)" $ do
      runMain nexto "VAR d : DWORD; END_VAR d := TIME_TO_DWORD(T#49d17h2m47s295ms);" 1 "d" `shouldBe` Right (VInt DWORD 4294967295)
      runMain nexto "VAR a : TIME; b : TIME := T#1ms; END_VAR a := a - b;" 1 "a" `shouldBe` Right (VTime TIME 4294967295)
      runMain nexto {pOverflow = Saturate} "VAR a : TIME; b : TIME := T#1ms; END_VAR a := a - b;" 1 "a" `shouldBe` Right (VTime TIME 0)
      runMain nexto {pTimeRange = TimeSigned} "VAR a : TIME; b : TIME := T#1ms; END_VAR a := a - b;" 1 "a" `shouldBe` Right (VTime TIME (-1))
      runMain nexto "VAR x : REAL := 3.0E9; t : TIME; END_VAR t := REAL_TO_TIME(x);" 1 "t" `shouldBe` Right (VTime TIME 3000000000)
      fmap fst (rejectKind nexto {pTimeRange = TimeSigned} (unit "VAR d : DWORD; END_VAR\nd := TIME_TO_DWORD(T#49d17h2m47s295ms);")) `shouldBe` Just "value-out-of-limits"
      fmap fst (rejectKind nexto (unit "VAR t : TIME := T#-5ms; END_VAR\nt := t;")) `shouldBe` Just "value-out-of-limits"
    it "subrange-initial: zero starts a range that holds 0 at 0, lower-bound at its lower bound (NX-TYPE-35, TC-TYPE-21)" $ do
      runMain nexto "VAR t : INT (-40..120); END_VAR" 1 "t" `shouldBe` Right (VInt INT 0)
      runMain nexto {pSubrangeInitial = SubrangeLowerBound} "VAR t : INT (-40..120); END_VAR" 1 "t" `shouldBe` Right (VInt INT (-40))
  describe "literals, shifts, ADR of a POU, CONCAT" $ do
    it "a typed literal beyond a signed type's range but within its width is a bit pattern (NX-LEX-33); tecomat rejects it" $ do
      runMain nexto "VAR d : DINT := DINT#16#FFFFFFFF; i : INT; END_VAR i := INT#16#8000;" 1 "i" `shouldBe` Right (VInt INT (-32768))
      runMain nexto "VAR d : DINT := DINT#16#FFFFFFFE; END_VAR" 1 "d" `shouldBe` Right (VInt DINT (-2))
      fmap fst (rejectKind nexto "PROGRAM MAIN\nVAR d : DINT := DINT#16#1FFFFFFFF; END_VAR\nEND_PROGRAM\n") `shouldBe` Just "value-out-of-limits"
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR d : DINT := DINT#16#FFFFFFFF; END_VAR\nEND_PROGRAM\n") `shouldBe` Just "value-out-of-limits"
    it "a shifted constant takes the smallest type that holds it, whatever the context (NX-OP-50)" $ do
      runMain nexto "VAR w : WORD; END_VAR w := SHL(16#45, 2);" 1 "w" `shouldBe` Right (VInt WORD 0x14)
      runMain nexto "VAR w : WORD; END_VAR w := ROL(16#145, 8);" 1 "w" `shouldBe` Right (VInt WORD 0x4501)
      runMain tecomat "VAR w : WORD; END_VAR w := SHL(16#45, 2);" 1 "w" `shouldBe` Right (VInt WORD 0x114)
    it "ADR of a function is a DWORD, not 0, the same each time, another for another POU (NX-TYPE-79)" $ do
      let src = "FUNCTION f : INT\nf := 1;\nEND_FUNCTION\nFUNCTION g : INT\ng := 2;\nEND_FUNCTION\nPROGRAM MAIN\nVAR a, b : DWORD; same, differ : BOOL; END_VAR\na := ADR(f); b := ADR(g); same := a = ADR(f) AND a <> 0; differ := a <> b;\nEND_PROGRAM\n"
      runUnit nexto src 1 "MAIN.same" `shouldBe` Right (VBool True)
      runUnit nexto src 1 "MAIN.differ" `shouldBe` Right (VBool True)
    it "CONCAT has two inputs under standard-library = codesys, more under iec (NX-STR-6, TC-STR-7)" $ do
      fmap fst (rejectKind nexto "PROGRAM MAIN\nVAR txt : STRING; END_VAR\ntxt := CONCAT('a', 'b', 'c');\nEND_PROGRAM\n") `shouldBe` Just "too-many-arguments"
      runMain nexto {pStandardLibrary = LibraryIec} "VAR txt : STRING; END_VAR txt := CONCAT('a', 'b', 'c');" 1 "txt" `shouldBe` Right (VString "abc")
      runMain nexto "VAR txt : STRING; END_VAR txt := CONCAT(STR1 := 'a', STR2 := 'b');" 1 "txt" `shouldBe` Right (VString "ab")
  describe "located BOOLs, BITADR, pack_mode" $ do
    it "a BOOL at a byte or word address is that whole first byte, 1 or 0 (NX-TYPE-18); the IEC core wants a bit address" $ do
      let body = "VAR lamp AT %QW4 : BOOL; raw AT %QB4 : BYTE; next AT %QB5 : BYTE; END_VAR raw := 16#F0; next := 16#AA; lamp := TRUE;"
      runMain nexto body 1 "raw" `shouldBe` Right (VInt BYTE 1)
      runMain nexto body 1 "next" `shouldBe` Right (VInt BYTE 0xAA)
      runMain nexto (body <> " raw := 16#10;") 1 "lamp" `shouldBe` Right (VBool True)
      rejectKind tecomat "PROGRAM MAIN\nVAR lamp AT %QB4 : BOOL; END_VAR\nlamp := TRUE;\nEND_PROGRAM\n" `shouldBe` Just ("type-mismatch", 2)
    it "BITADR gives an input's bit offset with the segment's mark: %IX2.3 is 16#80000013, %IB1 16#80000008 (NX-OP-69)" $ do
      runMain nexto "VAR b AT %IX2.3 : BOOL; w AT %IB1 : BYTE; o1, o2 : DWORD; END_VAR o1 := BITADR(b); o2 := BITADR(w);" 1 "o1" `shouldBe` Right (VInt DWORD 0x80000013)
      runMain nexto "VAR b AT %IX2.3 : BOOL; w AT %IB1 : BYTE; o1, o2 : DWORD; END_VAR o1 := BITADR(b); o2 := BITADR(w);" 1 "o2" `shouldBe` Right (VInt DWORD 0x80000008)
    it "BITADR of an output or of a variable without an address is rejected: the manual gives no value for them" $ do
      rejectKind nexto "PROGRAM MAIN\nVAR q AT %QX0.1 : BOOL; o : DWORD; END_VAR\no := BITADR(q);\nEND_PROGRAM\n" `shouldBe` Just ("not-a-variable", 3)
      rejectKind nexto "PROGRAM MAIN\nVAR q : BOOL; o : DWORD; END_VAR\no := BITADR(q);\nEND_PROGRAM\n" `shouldBe` Just ("not-a-variable", 3)
    it "pack_mode caps each member's alignment and the structure's (NX-PRAGMA-11): a DINT after a BOOL lies at 1, 2 or 4" $ do
      let unit pack = "{attribute 'pack_mode' := '" <> pack <> "'}\nTYPE Rec : STRUCT flag : BOOL; big : DINT; END_STRUCT END_TYPE\nPROGRAM MAIN\nVAR r1 : Rec; off : DWORD; size : UDINT; END_VAR\noff := ADR(r1.big) - ADR(r1.flag); size := SIZEOF(r1);\nEND_PROGRAM\n"
          natural = "TYPE Rec : STRUCT flag : BOOL; big : DINT; END_STRUCT END_TYPE\nPROGRAM MAIN\nVAR r1 : Rec; off : DWORD; size : UDINT; END_VAR\noff := ADR(r1.big) - ADR(r1.flag); size := SIZEOF(r1);\nEND_PROGRAM\n"
      [runUnit nexto (unit p) 1 "MAIN.off" | p <- ["0", "1", "2", "4", "8"]] `shouldBe` map (Right . VInt DWORD) [1, 1, 2, 4, 4]
      [runUnit nexto (unit p) 1 "MAIN.size" | p <- ["1", "2"]] `shouldBe` map (Right . VInt UDINT) [5, 6]
      runUnit nexto natural 1 "MAIN.off" `shouldBe` Right (VInt DWORD 4)
    it "a pack_mode other than 0, 1, 2, 4, 8 is rejected" $
      rejectKind nexto "{attribute 'pack_mode' := '3'}\nTYPE Rec : STRUCT flag : BOOL; END_STRUCT END_TYPE\nPROGRAM MAIN\nVAR r1 : Rec; END_VAR\nr1.flag := TRUE;\nEND_PROGRAM\n" `shouldBe` Just ("value-out-of-limits", 2)
  describe "MUX (NX-OP-67)" $
    it "computes only the input K selects; under index-out-of-range = clamp, the one the clamped K selects" $ do
      runMain nexto "VAR x, pick : INT; END_VAR pick := 1; x := MUX(pick, 10, 20, 30);" 1 "x" `shouldBe` Right (VInt INT 20)
      runMain nexto {pIndexOutOfRange = IndexClamp} "VAR x, pick : INT; END_VAR pick := 7; x := MUX(pick, 10, 20, 30);" 1 "x" `shouldBe` Right (VInt INT 30)
      runMain nexto {pIndexOutOfRange = IndexClamp} "VAR x, pick : INT; END_VAR pick := -2; x := MUX(pick, 10, 20, 30);" 1 "x" `shouldBe` Right (VInt INT 10)
  describe "VAR_CONFIG (NX-VAR-14, NX-VAR-15)" $ do
    let unit body = "FUNCTION_BLOCK Relay\nVAR\n  xIn AT %I* : BOOL;\n  xOut AT %Q* : BOOL;\nEND_VAR\nxOut := xIn;\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR\n  rl : Relay;\n  img AT %QX0.2 : BOOL;\n  sw AT %IX0.5 : BOOL;\n  early : BOOL;\nEND_VAR\n" <> body <> "\nEND_PROGRAM\nVAR_CONFIG\n  MAIN.rl.xIn AT %IX0.5 : BOOL;\n  MAIN.rl.xOut AT %QX0.2 : BOOL;\nEND_VAR\n"
    it "an input placed by VAR_CONFIG is read before the task, an output written to the image after it" $ do
      let src = unit "rl(); early := img;"
          on = Scan [("%IX0.5", SBool True)]
      runCalls nexto src [on] "MAIN.rl.xOut" `shouldBe` Right (VBool True)
      runCalls nexto src [on] "MAIN.early" `shouldBe` Right (VBool False) -- the image has it after the task only
      runCalls nexto src [on, Scan []] "MAIN.early" `shouldBe` Right (VBool True)
      runCalls nexto src [on, Scan [("%IX0.5", SBool False)]] "MAIN.rl.xOut" `shouldBe` Right (VBool False)
    it "the IEC core has no incomplete address" $
      rejectKind tecomat "FUNCTION_BLOCK R\nVAR\n  xIn AT %I* : BOOL;\nEND_VAR\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR r1 : R; END_VAR\nr1();\nEND_PROGRAM\n" `shouldSatisfy` maybe False ((== 3) . snd)
    it "an incomplete address outside an FB's VAR is rejected" $
      rejectKind nexto "PROGRAM MAIN\nVAR\n  xIn AT %I* : BOOL;\nEND_VAR\nxIn := TRUE;\nEND_PROGRAM\n" `shouldBe` Just ("section-not-allowed", 3)
  describe "UNION (NX-TYPE-72, NX-TYPE-73)" $ do
    let unionSrc decls body = "TYPE U :\nUNION\n" <> decls <> "\nEND_UNION\nEND_TYPE\nPROGRAM MAIN\nVAR u : U; a : ARRAY [1..2] OF U; x : DWORD; b : BYTE; rv : REAL; txt2 : STRING; p : POINTER TO BYTE; END_VAR\n" <> body <> "\nEND_PROGRAM\n"
    it "a REAL member reads as its IEEE 754 pattern in a DWORD member" $ do
      runUnit nexto (unionSrc "f : REAL; d : DWORD;" "u.f := 1.0; x := u.d;") 1 "MAIN.x" `shouldBe` Right (VInt DWORD 0x3F800000)
      runUnit nexto (unionSrc "f : REAL; d : DWORD;" "u.d := 16#40490FDB; rv := u.f;") 1 "MAIN.rv" `shouldBe` Right (VReal 3.1415927)
    it "a structure member's fields lie at their offsets, with padding" $
      runUnit nexto (unionSrc "st : STRUCT c : BYTE; w : WORD; END_STRUCT; raw : ARRAY [0..3] OF BYTE;" "u.st.w := 16#1234; b := u.raw[2];") 1 "MAIN.b" `shouldBe` Right (VInt BYTE 0x34)
    it "writing a short member keeps the bytes beyond it" $
      runUnit nexto (unionSrc "d : DWORD; lo : BYTE;" "u.d := 16#11223344; u.lo := 16#FF; x := u.d;") 1 "MAIN.x" `shouldBe` Right (VInt DWORD 0x112233FF)
    it "a STRING member shares its characters' bytes" $
      runUnit nexto (unionSrc "txt : STRING(3); code : ARRAY [0..3] OF BYTE;" "u.code[0] := 72; u.code[1] := 105; txt2 := u.txt;") 1 "MAIN.txt2" `shouldBe` Right (VString "Hi")
    it "unions in an array are separate, and a pointer reaches a member's byte" $ do
      runUnit nexto (unionSrc "d : DWORD; bs : ARRAY [0..3] OF BYTE;" "a[1].d := 16#AABBCCDD; a[2].d := 1; p := ADR(a[1].d) + 1; b := p^;") 1 "MAIN.b" `shouldBe` Right (VInt BYTE 0xCC)
      runUnit nexto (unionSrc "d : DWORD; bs : ARRAY [0..3] OF BYTE;" "a[1].d := 16#AABBCCDD; a[2].d := 1; x := a[2].d;") 1 "MAIN.x" `shouldBe` Right (VInt DWORD 1)
    it "the bytes of a value read back as the value (integers of every width, REAL, LREAL, TIME under each time-range)" $
      property $ \(n :: Integer) (f :: Float) (d :: Double) ->
        let ly r = layout (const []) (const Nothing) r
            bytes = layout (const []) (const Nothing) TimeUnsigned
            signedTime = wrapInt TIME n
            unsignedTime = n `mod` 2 ^ (32 :: Int)
         in and [decode bytes (TElem e) (encode bytes (TElem e) (VInt e (wrapInt e n))) == VInt e (wrapInt e n) | e <- allElems, isInt e]
              && decode bytes (TElem REAL) (encode bytes (TElem REAL) (VReal f)) == VReal f
              && decode bytes (TElem LREAL) (encode bytes (TElem LREAL) (VLReal d)) == VLReal d
              && decode (ly TimeSigned) (TElem TIME) (encode (ly TimeSigned) (TElem TIME) (VTime TIME signedTime)) == VTime TIME signedTime
              && decode (ly TimeUnsigned) (TElem TIME) (encode (ly TimeUnsigned) (TElem TIME) (VTime TIME unsignedTime)) == VTime TIME unsignedTime
    it "a member that is an FB instance, or has an initial value, is rejected" $ do
      fmap fst (rejectKind nexto (unionSrc "t : TON; d : DWORD;" "")) `shouldBe` Just "type-mismatch"
      fmap fst (rejectKind nexto (unionSrc "d : DWORD := 5;" "")) `shouldBe` Just "section-not-allowed"
  describe "pointers, resets, check functions" $ do
    it "FB_Init is told whether the retentive variables are initialised: at the start and a cold reset, not at a warm one (NX-POU-35)" $ do
      let src = "VAR_GLOBAL trace : DINT; END_VAR\nFUNCTION_BLOCK Dev\nMETHOD FB_Init : BOOL\nVAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; END_VAR\ntrace := trace * 10 + BOOL_TO_DINT(bInitRetains) + 1;\nEND_METHOD\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR d : Dev; END_VAR\nEND_PROGRAM\n"
      runCalls nexto src [Scan [], Reset WarmReset, Scan [], Reset ColdReset, Scan []] "trace" `shouldBe` Right (VInt DINT 2)
      runCalls nexto ("VAR_GLOBAL RETAIN keep : DINT; END_VAR\n" <> T.replace "trace := trace" "keep := keep * 10 + BOOL_TO_DINT(bInitRetains) + 1; trace := trace" src) [Scan [], Reset WarmReset, Scan [], Reset WarmReset, Scan []] "keep" `shouldBe` Right (VInt DINT 211)
    it "an instance's FB_Init runs after those of the instances it contains, with the inputs given at its declaration (NX-POU-35)" $ do
      let src = "VAR_GLOBAL trace : DINT; END_VAR\nFUNCTION_BLOCK Inner\nMETHOD FB_Init : BOOL\nVAR_INPUT bInitRetains, bInCopyCode : BOOL; n : DINT; END_VAR\ntrace := trace * 10 + n;\nEND_METHOD\nEND_FUNCTION_BLOCK\nFUNCTION_BLOCK Outer\nVAR a : Inner(n := 1); b : Inner(n := 2); END_VAR\nMETHOD FB_Init : BOOL\nVAR_INPUT bInitRetains, bInCopyCode : BOOL; END_VAR\ntrace := trace * 10 + 3;\nEND_METHOD\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR k : DINT := 4; o : Outer; i : Inner(n := k + 1); END_VAR\nEND_PROGRAM\n"
      runCalls nexto src [Scan []] "trace" `shouldBe` Right (VInt DINT 1235)
    it "an input at a declaration that the FB_Init does not declare is rejected (NX-POU-35)" $ do
      let src = "FUNCTION_BLOCK Dev\nVAR x : INT; END_VAR\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR d : Dev(n := 1); END_VAR\nEND_PROGRAM\n"
      rejectKind nexto src `shouldBe` Just ("unknown-parameter", 5)
    it "a computed initial value is computed again at a reset that initialises its variable (NX-VAR-24, NX-VAR-21)" $ do
      let src = "VAR_GLOBAL base : INT := 5; END_VAR\nPROGRAM MAIN\nVAR x : INT := base * 2; END_VAR\nVAR RETAIN kept : INT := base * 3; END_VAR\nx := x + 1; kept := kept + 1; base := 7;\nEND_PROGRAM\n"
      runCalls nexto src [Scan [], Reset WarmReset] "MAIN.x" `shouldBe` Right (VInt INT 10)
      runCalls nexto src [Scan [], Reset WarmReset] "MAIN.kept" `shouldBe` Right (VInt INT 16)
      runCalls nexto src [Scan [], Reset ColdReset] "MAIN.kept" `shouldBe` Right (VInt INT 15)
    it "ADR, ^ and byte arithmetic over an array (NX-TYPE-76, NX-TYPE-77)" $ do
      let body = "VAR a : ARRAY [0..4] OF INT := [10, 20, 30, 40, 50]; p : POINTER TO INT; x, y : INT; END_VAR p := ADR(a[0]); x := p[3]; p := p + 4; y := p^;"
      runMain nexto body 1 "x" `shouldBe` Right (VInt INT 40)
      runMain nexto body 1 "y" `shouldBe` Right (VInt INT 30)
    it "dereferencing 0 is null-pointer" $
      errorOf nexto "VAR p : POINTER TO INT; x : INT; END_VAR x := p^;" 1 `shouldBe` Just (1, "null-pointer")
    it "where no variable of its type starts, a pointer reads and writes the bytes at its address as its type (NX-TYPE-75)" $ do
      let body = "VAR a : ARRAY [0..1] OF INT := [16#0102, 16#0304]; p : POINTER TO INT; x : INT; END_VAR p := ADR(a[0]); x := (p + 1)^; p := p + 1; p^ := 16#7F7F;"
      runMain nexto body 1 "x" `shouldBe` Right (VInt INT 0x0401)
      runMain nexto body 1 "a[0]" `shouldBe` Right (VInt INT 0x7F02)
      runMain nexto body 1 "a[1]" `shouldBe` Right (VInt INT 0x037F)
      let longer = "VAR a : ARRAY [1..4] OF INT := [1, 2, 3, 4]; more : ARRAY [0..15] OF INT; p : POINTER TO ARRAY [0..7] OF INT; x : INT; END_VAR p := ADR(a[3]); x := p^[1];"
      runMain nexto longer 1 "x" `shouldBe` Right (VInt INT 4)
    it "a pointer whose target's bytes reach beyond every variable is null-pointer (NX-ERR-21)" $
      errorOf nexto "VAR p : POINTER TO ARRAY [0..30000] OF INT; x : INT; END_VAR p := ADR(x); x := p^[0];" 1 `shouldBe` Just (1, "null-pointer")
    it "CheckBounds' result is the index used (NX-ERR-7)" $ do
      let src = "FUNCTION CheckBounds : DINT\nVAR_INPUT index, lower, upper : DINT; END_VAR\nIF index > upper THEN CheckBounds := upper; ELSE CheckBounds := index; END_IF\nEND_FUNCTION\nPROGRAM MAIN\nVAR a : ARRAY [0..7] OF BOOL; b : INT := 10; END_VAR\na[b] := TRUE;\nEND_PROGRAM\n"
      runUnit nexto src 1 "MAIN.a[7]" `shouldBe` Right (VBool True)
