-- | The nexto dialect's conversions and library (standard-library =
-- codesys): CODESYS's conversion functions (Nexto catalogue §3.2), the
-- functions and function blocks of util.library, RTC and TIME(). Expected
-- values are the manual's printed results or worked out by hand from the
-- rules named; none was obtained by running the code.
module IEC.NextoLibrarySpec (spec) where

import Data.Text (Text)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Support.Iec
import Test.Hspec

-- | One assignment @x := expr@ with x of the given type, run once under the
-- nexto preset: x's value.
assigned :: Text -> Text -> Either Text Value
assigned ty e = runMain nexto ("VAR x : " <> ty <> "; END_VAR x := " <> e <> ";") 1 "x"

str :: Text -> Either Text Value
str = Right . VString

spec :: Spec
spec = describe "the nexto dialect's conversions and library (standard-library = codesys)" $ do
  describe "BOOL and the time types (NX-CONV-12..18)" $ do
    it "TRUE is 1 in the type's unit (NX-CONV-14, NX-CONV-15)" $ do
      assigned "TIME" "BOOL_TO_TIME(TRUE)" `shouldBe` Right (VTime TIME 1)
      assigned "TOD" "BOOL_TO_TOD(TRUE)" `shouldBe` Right (VTod 1)
      assigned "DATE" "BOOL_TO_DATE(FALSE)" `shouldBe` Right (VDate 0)
      assigned "DT" "BOOL_TO_DT(TRUE)" `shouldBe` Right (VDT 1000)
    it "a time type is TRUE when not 0 (NX-CONV-16, NX-CONV-18)" $ do
      assigned "BOOL" "TIME_TO_BOOL(T#5ms)" `shouldBe` Right (VBool True)
      assigned "BOOL" "DATE_TO_BOOL(D#1970-01-01)" `shouldBe` Right (VBool False)
      assigned "BOOL" "TOD_TO_BOOL(TOD#00:00:00.001)" `shouldBe` Right (VBool True)
  describe "the time types as numbers: TIME, TOD in ms, DATE, DT in s (NX-CONV-26, NX-CONV-29)" $ do
    it "the manual's examples, narrowing keeping the low bytes (NX-CONV-28, NX-CONV-30)" $ do
      assigned "DWORD" "TIME_TO_DWORD(T#5m)" `shouldBe` Right (VInt DWORD 300000)
      assigned "SINT" "TOD_TO_SINT(TOD#00:00:00.012)" `shouldBe` Right (VInt SINT 12)
      -- 14 days = 1209600 s = 16#12_7500: INT keeps 16#7500
      assigned "INT" "DATE_TO_INT(D#1970-01-15)" `shouldBe` Right (VInt INT 29952)
      -- 1227905 s = 16#12_BC81: BYTE keeps 16#81
      assigned "BYTE" "DT_TO_BYTE(DT#1970-01-15-05:05:05)" `shouldBe` Right (VInt BYTE 129)
    it "under narrow-int = saturate the nearest bound" $
      runMain nexto {pNarrowInt = NarrowSaturate} "VAR x : INT; END_VAR x := DATE_TO_INT(D#1970-01-15);" 1 "x" `shouldBe` Right (VInt INT 32767)
    it "numbers to TOD, DATE and DT" $ do
      assigned "TOD" "DWORD_TO_TOD(3600000)" `shouldBe` Right (VTod 3600000)
      assigned "DATE" "UDINT_TO_DATE(86400)" `shouldBe` Right (VDate 86400000)
      -- a DATE is the midnight of the day the seconds fall in
      assigned "DATE" "UDINT_TO_DATE(90000)" `shouldBe` Right (VDate 86400000)
      assigned "DT" "DWORD_TO_DT(3661)" `shouldBe` Right (VDT 3661000)
      assigned "LREAL" "DT_TO_LREAL(DT#1970-01-01-00:01:00)" `shouldBe` Right (VLReal 60)
  describe "to and from STRING (NX-CONV-11, NX-CONV-25, NX-CONV-27, NX-CONV-30..33)" $ do
    it "a time type gives its constant; a DT without seconds when they are 0 (NX-CONV-28, NX-CONV-30)" $ do
      assigned "STRING" "TIME_TO_STRING(T#12ms)" `shouldBe` str "T#12ms"
      assigned "STRING" "DT_TO_STRING(DT#1998-02-13-14:20:00)" `shouldBe` str "DT#1998-02-13-14:20"
      assigned "STRING" "DT_TO_STRING(DT#1998-02-13-14:20:05)" `shouldBe` str "DT#1998-02-13-14:20:05"
      assigned "STRING[4]" "TIME_TO_STRING(T#12ms)" `shouldBe` str "T#12"
    it "at most 16 significant digits, the 16th rounded (NX-CONV-25)" $ do
      -- binary64 1.2345678901234567 is 1.23456789012345669...
      assigned "STRING" "LREAL_TO_STRING(LREAL#1.2345678901234567)" `shouldBe` str "1.234567890123457"
      assigned "STRING" "LREAL_TO_STRING(LREAL#0.1)" `shouldBe` str "0.1"
    it "STRING to a time type reads its literal; other text gives 0 (NX-CONV-32, NX-CONV-33)" $ do
      assigned "TIME" "STRING_TO_TIME('T#127ms')" `shouldBe` Right (VTime TIME 127)
      assigned "TIME" "STRING_TO_TIME('t#1m35s')" `shouldBe` Right (VTime TIME 95000)
      assigned "TIME" "STRING_TO_TIME('abc')" `shouldBe` Right (VTime TIME 0)
      assigned "TIME" "STRING_TO_TIME('D#2000-01-01')" `shouldBe` Right (VTime TIME 0)
      assigned "TOD" "STRING_TO_TOD('TOD#01:00:00')" `shouldBe` Right (VTod 3600000)
      assigned "DATE" "STRING_TO_DATE('D#1970-01-02')" `shouldBe` Right (VDate 86400000)
      -- 10270 days and 14:20 (51600 s): 887379600 s
      assigned "DT" "STRING_TO_DT('DT#1998-02-13-14:20')" `shouldBe` Right (VDT 887379600000)
    it "STRING to a number goes through the integer and keeps the low byte (NX-CONV-31, NX-CONV-33)" $ do
      assigned "BYTE" "STRING_TO_BYTE('500')" `shouldBe` Right (VInt BYTE 244)
      assigned "WORD" "STRING_TO_WORD('abc34')" `shouldBe` Right (VInt WORD 0)
  describe "TRUNC, TRUNC_INT, ANY_TO (NX-CONV-34..38)" $ do
    it "TRUNC_INT gives the integer part as INT (NX-CONV-36, NX-CONV-37)" $ do
      assigned "INT" "TRUNC_INT(1.9)" `shouldBe` Right (VInt INT 1)
      assigned "INT" "TRUNC_INT(-1.4)" `shouldBe` Right (VInt INT (-1))
      assigned "DINT" "TRUNC_INT(REAL#1.9)" `shouldBe` Right (VInt DINT 1)
    it "TRUNC gives the context's type (NX-CONV-34, NX-CONV-35)" $ do
      assigned "DINT" "TRUNC(-1.4)" `shouldBe` Right (VInt DINT (-1))
      assigned "INT" "TRUNC(REAL#1.9)" `shouldBe` Right (VInt INT 1)
    it "ANY_TO_INT of a REAL rounds as REAL_TO_INT does (NX-CONV-38)" $ do
      runMain nexto "VAR re : REAL := 1.234; i : INT; END_VAR i := ANY_TO_INT(re);" 1 "i" `shouldBe` Right (VInt INT 1)
      runMain nexto "VAR re : REAL := 1.5; i : INT; END_VAR i := ANY_TO_INT(re);" 1 "i" `shouldBe` Right (VInt INT 2)
    it "ANY_TO_ takes any type, ANY_NUM_TO_ the numbers (NX-TYPE-86)" $ do
      assigned "LREAL" "ANY_NUM_TO_LREAL(DINT#7)" `shouldBe` Right (VLReal 7)
      assigned "DINT" "ANY_TO_DINT(T#2s)" `shouldBe` Right (VInt DINT 2000)
      assigned "STRING" "ANY_TO_STRING(TRUE)" `shouldBe` str "TRUE"
      assigned "INT" "ANY_TO_INT(INT#5)" `shouldBe` Right (VInt INT 5)
      fmap fst (rejectKind nexto "PROGRAM MAIN\nVAR x : DINT; END_VAR\nx := ANY_NUM_TO_DINT(T#2s);\nEND_PROGRAM\n") `shouldBe` Just "type-mismatch"
  describe "LTIME in nanoseconds (NX-TYPE-33)" $ do
    it "TIME_TO_LTIME keeps the duration, LTIME_TO_TIME truncates to milliseconds" $ do
      assigned "LTIME" "TIME_TO_LTIME(T#5ms)" `shouldBe` Right (VTime LTIME 5000000)
      assigned "TIME" "LTIME_TO_TIME(TIME_TO_LTIME(T#1m2s3ms))" `shouldBe` Right (VTime TIME 62003)
      assigned "TIME" "LTIME_TO_TIME(LWORD_TO_LTIME(1999999))" `shouldBe` Right (VTime TIME 1)
    it "LTIME with the integers counts nanoseconds" $ do
      assigned "LINT" "LTIME_TO_LINT(TIME_TO_LTIME(T#1ms))" `shouldBe` Right (VInt LINT 1000000)
      assigned "LTIME" "LWORD_TO_LTIME(1500)" `shouldBe` Right (VTime LTIME 1500)
      -- 5 s = 5000000000 ns; DINT keeps its low 32 bits: 5000000000 - 2^32
      assigned "DINT" "LTIME_TO_DINT(TIME_TO_LTIME(T#5s))" `shouldBe` Right (VInt DINT 705032704)
  describe "under standard-library = iec the IEC core's conversions stay (tecomat)" $ do
    it "no CODESYS conversions" $ do
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR x : INT; END_VAR\nx := DATE_TO_INT(D#1970-01-15);\nEND_PROGRAM\n") `shouldBe` Just "undeclared-function"
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR x : INT; END_VAR\nx := TRUNC_INT(1.5);\nEND_PROGRAM\n") `shouldBe` Just "undeclared-function"
    it "IEC's BCD conversions: BCD_TO_INT of a bit string, an invalid digit is an error (TC-CONV-8, TC-CONV-15)" $ do
      runMain tecomat "VAR x : INT; END_VAR x := BCD_TO_INT(WORD#16#1234);" 1 "x" `shouldBe` Right (VInt INT 1234)
      errorOf tecomat "VAR x : INT; END_VAR x := BCD_TO_INT(WORD#16#12A4);" 1 `shouldBe` Just (1, "conversion")
    it "DT_TO_STRING keeps the seconds" $
      runMain tecomat "VAR x : STRING; END_VAR x := DT_TO_STRING(DT#1998-02-13-14:20:00);" 1 "x" `shouldBe` str "DT#1998-02-13-14:20:00"
  describe "util.library's functions and TIME() (NX-FB-34..37, NX-OP-87)" $ do
    it "BCD_TO_INT: -1 for a byte that is no BCD (NX-CONV-39)" $ do
      assigned "INT" "BCD_TO_INT(73)" `shouldBe` Right (VInt INT 49)
      assigned "INT" "BCD_TO_INT(151)" `shouldBe` Right (VInt INT 97)
      assigned "INT" "BCD_TO_INT(15)" `shouldBe` Right (VInt INT (-1))
      assigned "INT" "BCD_TO_INT(B := 16#A1)" `shouldBe` Right (VInt INT (-1))
    it "INT_TO_BCD: 255 outside 0..99 (NX-CONV-40)" $ do
      assigned "BYTE" "INT_TO_BCD(49)" `shouldBe` Right (VInt BYTE 73)
      assigned "BYTE" "INT_TO_BCD(97)" `shouldBe` Right (VInt BYTE 151)
      assigned "BYTE" "INT_TO_BCD(100)" `shouldBe` Right (VInt BYTE 255)
      assigned "BYTE" "INT_TO_BCD(-5)" `shouldBe` Right (VInt BYTE 255)
    it "a literal argument outside the parameter's type is rejected" $
      fmap fst (rejectKind nexto "PROGRAM MAIN\nVAR x : INT; END_VAR\nx := BCD_TO_INT(300);\nEND_PROGRAM\n") `shouldBe` Just "value-out-of-limits"
    it "EXTRACT reads bit N of X (NX-FB-35)" $ do
      assigned "BOOL" "EXTRACT(X := 81, N := 4)" `shouldBe` Right (VBool True)
      assigned "BOOL" "EXTRACT(X := 33, N := 0)" `shouldBe` Right (VBool True)
      assigned "BOOL" "EXTRACT(N := 1, X := 81)" `shouldBe` Right (VBool False)
    it "PUTBIT sets bit N of X to B (NX-FB-36)" $ do
      runMain nexto "VAR A, B, C : DWORD; END_VAR A := 38; B := PUTBIT(A, 4, TRUE); C := PUTBIT(A, 1, FALSE);" 1 "B" `shouldBe` Right (VInt DWORD 54)
      runMain nexto "VAR A, B, C : DWORD; END_VAR A := 38; B := PUTBIT(A, 4, TRUE); C := PUTBIT(A, 1, FALSE);" 1 "C" `shouldBe` Right (VInt DWORD 36)
    it "PACK makes B0..B7 a BYTE, B0 the lowest bit; an input left out is FALSE (NX-FB-37)" $ do
      assigned "BYTE" "PACK(B0 := TRUE, B1 := FALSE, B2 := TRUE, B3 := FALSE, B4 := FALSE, B5 := TRUE, B6 := FALSE, B7 := TRUE)" `shouldBe` Right (VInt BYTE 165)
      assigned "BYTE" "PACK(B7 := TRUE)" `shouldBe` Right (VInt BYTE 128)
    it "TIME() is the clock: T#0ms in the first cycle, 10 ms more in each (NX-OP-87)" $ do
      runMain nexto "VAR t : TIME; END_VAR t := TIME();" 1 "t" `shouldBe` Right (VTime TIME 0)
      runMain nexto "VAR t : TIME; END_VAR t := TIME();" 4 "t" `shouldBe` Right (VTime TIME 30)
    it "none of them under standard-library = iec" $ do
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR x : BOOL; END_VAR\nx := EXTRACT(81, 4);\nEND_PROGRAM\n") `shouldBe` Just "undeclared-function"
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR x : TIME; END_VAR\nx := TIME();\nEND_PROGRAM\n") `shouldBe` Just "undeclared-function"
  describe "util.library's function blocks and RTC (NX-FB-30..33, NX-FB-37..40)" $ do
    it "UNPACK splits B into B0..B7 (NX-FB-37)" $ do
      runMain nexto "VAR u : UNPACK; END_VAR u(B := 16#A5);" 1 "u.B0" `shouldBe` Right (VBool True)
      runMain nexto "VAR u : UNPACK; END_VAR u(B := 16#A5);" 1 "u.B1" `shouldBe` Right (VBool False)
      runMain nexto "VAR u : UNPACK; END_VAR u(B := 16#A5);" 1 "u.B7" `shouldBe` Right (VBool True)
    let levels = "VAR lv : ARRAY [1..5] OF INT := [70, 40, 50, 101, 100]; hy : HYSTERESIS; al : LIMITALARM; k : INT; END_VAR k := k + 1; hy(IN := lv[k], HIGH := 100, LOW := 50); al(IN := lv[k], HIGH := 100, LOW := 50);"
    it "HYSTERESIS: TRUE below LOW, FALSE above HIGH, else held (NX-FB-39)" $ do
      runMain nexto levels 1 "hy.OUT" `shouldBe` Right (VBool False)
      runMain nexto levels 2 "hy.OUT" `shouldBe` Right (VBool True)
      runMain nexto levels 3 "hy.OUT" `shouldBe` Right (VBool True)
      runMain nexto levels 4 "hy.OUT" `shouldBe` Right (VBool False)
    it "LIMITALARM: O above HIGH, U below LOW, IL between, limits included (NX-FB-40)" $ do
      runMain nexto levels 2 "al.U" `shouldBe` Right (VBool True)
      runMain nexto levels 3 "al.IL" `shouldBe` Right (VBool True)
      runMain nexto levels 4 "al.O" `shouldBe` Right (VBool True)
      runMain nexto levels 5 "al.IL" `shouldBe` Right (VBool True)
    it "LIN_TRAFO maps the input range on the output range; ERROR on an empty range or an input outside (NX-FB-38)" $ do
      let lin i lo hi = runMain nexto ("VAR t : LIN_TRAFO; END_VAR t(IN := " <> i <> ", IN_MIN := " <> lo <> ", IN_MAX := " <> hi <> ", OUT_MIN := 0.0, OUT_MAX := 100.0);") 1
      -- 14000 * 100 / 30000 = 46.666..., nearest binary32 46.666668
      lin "14000.0" "0.0" "30000.0" "t.OUT" `shouldBe` Right (VReal 46.666668)
      lin "15000.0" "0.0" "30000.0" "t.OUT" `shouldBe` Right (VReal 50)
      lin "14000.0" "0.0" "30000.0" "t.ERROR" `shouldBe` Right (VBool False)
      lin "10.0" "10.0" "10.0" "t.ERROR" `shouldBe` Right (VBool True)
      lin "-1.0" "0.0" "30000.0" "t.ERROR" `shouldBe` Right (VBool True)
      lin "-1.0" "0.0" "30000.0" "t.OUT" `shouldBe` Right (VReal 0)
    it "CHARCURVE interpolates between the points; ERR 4, 1, 2 (NX-FB-38)" $ do
      let curve inp n = runMain nexto ("VAR c : CHARCURVE; kl : ARRAY [0..10] OF POINT := [(X := 0, Y := 0), (X := 250, Y := 50), (X := 500, Y := 150), (X := 750, Y := 400), 7((X := 1000, Y := 1000))]; END_VAR c(IN := " <> inp <> ", N := " <> n <> ", P := kl);") 1
      -- between (500, 150) and (750, 400): slope 1
      curve "510" "5" "c.OUT" `shouldBe` Right (VInt INT 160)
      curve "510" "5" "c.ERR" `shouldBe` Right (VInt BYTE 0)
      -- between (0, 0) and (250, 50): 0 + 100 * 50 / 250 = 20
      curve "100" "5" "c.OUT" `shouldBe` Right (VInt INT 20)
      curve "1010" "5" "c.OUT" `shouldBe` Right (VInt INT 1000)
      curve "1010" "5" "c.ERR" `shouldBe` Right (VInt BYTE 2)
      curve "-10" "5" "c.ERR" `shouldBe` Right (VInt BYTE 2)
      curve "100" "1" "c.ERR" `shouldBe` Right (VInt BYTE 4)
      -- P[4].X = P[5].X = 1000: not increasing
      curve "100" "7" "c.ERR" `shouldBe` Right (VInt BYTE 1)
    it "a POU of the program hides a library FB of its name" $
      runUnit nexto "FUNCTION_BLOCK HYSTERESIS\nVAR_OUTPUT OUT : INT; END_VAR\nOUT := 7;\nEND_FUNCTION_BLOCK\nPROGRAM MAIN\nVAR h : HYSTERESIS; END_VAR\nh();\nEND_PROGRAM\n" 1 "MAIN.h.OUT" `shouldBe` Right (VInt INT 7)
    let clock = "VAR rt : RTC; en : BOOL; k : INT; END_VAR k := k + 1; en := k > 1; rt(EN := en, PDT := DT#2006-03-30-14:00:00);"
    it "RTC: DT#1970-01-01-00:00:00 and Q FALSE while EN is FALSE (NX-FB-31)" $ do
      runMain nexto clock 1 "rt.CDT" `shouldBe` Right (VDT 0)
      runMain nexto clock 1 "rt.Q" `shouldBe` Right (VBool False)
    it "RTC: from EN's rising edge, PDT plus the whole seconds since (NX-FB-32)" $ do
      -- the edge in cycle 2 (clock 10 ms); cycle 102 reads 1010 ms: 1 s later
      runMain nexto clock 2 "rt.CDT" `shouldBe` Right (VDT 1143727200000)
      runMain nexto clock 101 "rt.CDT" `shouldBe` Right (VDT 1143727200000)
      runMain nexto clock 102 "rt.CDT" `shouldBe` Right (VDT 1143727201000)
      runMain nexto clock 102 "rt.Q" `shouldBe` Right (VBool True)
    it "none of them under standard-library = iec" $
      fmap fst (rejectKind tecomat "PROGRAM MAIN\nVAR h : HYSTERESIS; END_VAR\nh();\nEND_PROGRAM\n") `shouldBe` Just "undeclared-type"
  describe "LTIME literals (NX-LEX-41)" $ do
    it "an LTIME# literal is an LTIME of nanoseconds (NX-LEX-41)" $ do
      -- 1 ms 2 us 44 ns = 1000000 + 2000 + 44 ns
      assigned "LTIME" "LTIME#1ms2us44ns" `shouldBe` Right (VTime LTIME 1002044)
      assigned "LINT" "LTIME_TO_LINT(LTIME#2us44ns)" `shouldBe` Right (VInt LINT 2044)
      fmap fst (rejectKind nexto "PROGRAM MAIN\nVAR x : TIME; END_VAR\nx := LTIME#5ms;\nEND_PROGRAM\n") `shouldBe` Just "type-mismatch"
