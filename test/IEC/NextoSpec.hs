-- | The nexto dialect: CODESYS V3 as the Nexto manual documents it, on the
-- IEC core. Expected values come from the rules named, worked out by hand.
module IEC.NextoSpec (spec) where

import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Support.Iec
import Test.Hspec

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
