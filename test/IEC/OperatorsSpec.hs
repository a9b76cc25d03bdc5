-- | The IEC operators, conversions and standard functions on values
-- (Stref.IEC.Operators, Stref.IEC.Conversions, Stref.IEC.Standard). Every
-- expected value is worked out by hand from the rule it names, not taken
-- from the code.
module IEC.OperatorsSpec (spec) where

import Data.Either (isLeft)
import Data.Text (Text)
import Stref.IEC.Conversions
import Stref.IEC.Operators
import Stref.IEC.Standard
import Stref.IEC.Syntax (BinOp (..), UnOp (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Test.Hspec

p0 :: Policies
p0 = tecomat

withOverflow :: Overflow -> Policies
withOverflow o = p0 {pOverflow = o}

int, dint, sint, usint, byte, word :: Integer -> Value
int = VInt INT
dint = VInt DINT
sint = VInt SINT
usint = VInt USINT
byte = VInt BYTE
word = VInt WORD

ms :: Integer -> Value
ms = VTime TIME

str :: Text -> Value
str = VString

kindOf :: Either Fault a -> Maybe Text
kindOf = either (Just . faultKind) (const Nothing)

isNaNValue :: Either Fault Value -> Bool
isNaNValue = \case
  Right (VReal x) -> isNaN x
  Right (VLReal x) -> isNaN x
  _ -> False

-- a standard function with STRING[255] for string arguments, INT for integers
call :: Policies -> Text -> [Value] -> Either Fault Value
call p f vs = standard p f (map typeOfValue vs) vs
  where
    typeOfValue = \case
      VString _ -> TString False 255
      v -> maybe (TElem INT) TElem (valueElem v)

s255 :: Type
s255 = TString False 255

spec :: Spec
spec = do
  describe "integer overflow (TC-OP-20)" $ do
    it "INT 32767 + 1 wraps to -32768 under wrap" $
      binary (withOverflow Wrap) BAdd (int 32767) (int 1) `shouldBe` Right (int (-32768))
    it "INT 32767 + 1 stays 32767 under saturate" $
      binary (withOverflow Saturate) BAdd (int 32767) (int 1) `shouldBe` Right (int 32767)
    it "INT 32767 + 1 is an overflow error under trap" $
      kindOf (binary (withOverflow Trap) BAdd (int 32767) (int 1)) `shouldBe` Just "overflow"
    it "INT -32768 - 1 saturates to -32768" $
      binary (withOverflow Saturate) BSub (int (-32768)) (int 1) `shouldBe` Right (int (-32768))
    it "SINT 100 * 2 = 200 wraps to -56" $
      binary (withOverflow Wrap) BMul (sint 100) (sint 2) `shouldBe` Right (sint (-56))
    it "USINT 0 - 1 is 255 under wrap, 0 under saturate" $ do
      binary (withOverflow Wrap) BSub (usint 0) (usint 1) `shouldBe` Right (usint 255)
      binary (withOverflow Saturate) BSub (usint 0) (usint 1) `shouldBe` Right (usint 0)
    it "a bit string wraps whatever the policy: WORD 16#FFFF + 1 = 0" $
      binary (withOverflow Saturate) BAdd (word 65535) (word 1) `shouldBe` Right (word 0)
    it "-(-32768) follows the policy" $ do
      unary (withOverflow Wrap) UNeg (int (-32768)) `shouldBe` Right (int (-32768))
      unary (withOverflow Saturate) UNeg (int (-32768)) `shouldBe` Right (int 32767)
      kindOf (unary (withOverflow Trap) UNeg (int (-32768))) `shouldBe` Just "overflow"
    it "INT -32768 / -1 overflows" $ do
      binary (withOverflow Wrap) BDiv (int (-32768)) (int (-1)) `shouldBe` Right (int (-32768))
      binary (withOverflow Saturate) BDiv (int (-32768)) (int (-1)) `shouldBe` Right (int 32767)

  describe "integer division and MOD (TC-OP-21..24)" $ do
    let euclid = p0 {pModSign = ModSignEuclidean}
    it "truncates toward zero under mod-sign=dividend" $ do
      binary p0 BDiv (int 7) (int 2) `shouldBe` Right (int 3)
      binary p0 BDiv (int (-7)) (int 2) `shouldBe` Right (int (-3))
      binary p0 BDiv (int 7) (int (-2)) `shouldBe` Right (int (-3))
    it "floors for a non-negative remainder under euclidean" $ do
      binary euclid BDiv (int (-7)) (int 2) `shouldBe` Right (int (-4))
      binary euclid BDiv (int 7) (int (-2)) `shouldBe` Right (int (-3))
      binary euclid BDiv (int (-7)) (int (-2)) `shouldBe` Right (int 4)
    it "MOD has the dividend's sign under dividend" $ do
      binary p0 BMod (int (-7)) (int 2) `shouldBe` Right (int (-1))
      binary p0 BMod (int 7) (int (-2)) `shouldBe` Right (int 1)
      binary p0 BMod (int (-7)) (int (-2)) `shouldBe` Right (int (-1))
    it "MOD is never negative under euclidean" $ do
      binary euclid BMod (int (-7)) (int 2) `shouldBe` Right (int 1)
      binary euclid BMod (int (-7)) (int (-2)) `shouldBe` Right (int 1)
    it "x MOD 0 is 0 under mod-zero=zero, an error under error" $ do
      binary p0 BMod (int 5) (int 0) `shouldBe` Right (int 0)
      kindOf (binary p0 {pModZero = ModZeroError} BMod (int 5) (int 0)) `shouldBe` Just "division-by-zero"
    it "x / 0 follows div-zero" $ do
      kindOf (binary p0 BDiv (int 5) (int 0)) `shouldBe` Just "division-by-zero"
      kindOf (binary p0 {pDivZero = DivZeroTrap} BDiv (int 5) (int 0)) `shouldBe` Just "division-by-zero"
      binary p0 {pDivZero = DivZeroZero} BDiv (int 5) (int 0) `shouldBe` Right (int 0)

  describe "REAL and LREAL (TC-TYPE-8, TC-OP-26)" $ do
    it "REAL arithmetic rounds to binary32: 0.1 + 0.2 = 0.3" $
      binary p0 BAdd (VReal 0.1) (VReal 0.2) `shouldBe` Right (VReal 0.3)
    it "LREAL arithmetic rounds to binary64: 0.1 + 0.2 = 0.30000000000000004" $
      binary p0 BAdd (VLReal 0.1) (VLReal 0.2) `shouldBe` Right (VLReal 0.30000000000000004)
    it "x / 0.0 is IEEE under real-div-zero=ieee" $ do
      binary p0 BDiv (VReal 1) (VReal 0) `shouldBe` Right (VReal (1 / 0))
      binary p0 BDiv (VReal (-1)) (VReal 0) `shouldBe` Right (VReal (-1 / 0))
      binary p0 BDiv (VReal 0) (VReal 0) `shouldSatisfy` isNaNValue
    it "x / 0.0 is an error under real-div-zero=error" $
      kindOf (binary p0 {pRealDivZero = RealDivZeroError} BDiv (VReal 1) (VReal 0)) `shouldBe` Just "division-by-zero"
    it "REAL overflow stays infinite under ieee, saturates under saturate" $ do
      binary p0 BMul (VReal 3.0e38) (VReal 10) `shouldBe` Right (VReal (1 / 0))
      binary p0 {pRealOverflow = RealOverflowSaturate} BMul (VReal 3.0e38) (VReal 10) `shouldBe` Right (VReal 3.4028235e38)
      binary p0 {pRealOverflow = RealOverflowSaturate} BMul (VReal (-3.0e38)) (VReal 10) `shouldBe` Right (VReal (-3.4028235e38))
    it "REAL MOD has the dividend's sign (TC-OP-11)" $ do
      binary p0 BMod (VReal 5.5) (VReal 2) `shouldBe` Right (VReal 1.5)
      binary p0 BMod (VReal (-5.5)) (VReal 2) `shouldBe` Right (VReal (-1.5))
    it "NaN compares unequal to everything" $ do
      let nan = VReal (0 / 0)
      binary p0 BEq nan nan `shouldBe` Right (VBool False)
      binary p0 BNe nan nan `shouldBe` Right (VBool True)
      binary p0 BLt nan (VReal 1) `shouldBe` Right (VBool False)

  describe "** and EXPT (TC-OP-17, TC-OP-25)" $ do
    it "integer powers are exact" $
      binary p0 BPow (int 2) (int 10) `shouldBe` Right (int 1024)
    it "an integer power that leaves the range follows overflow" $ do
      binary (withOverflow Wrap) BPow (int 2) (int 15) `shouldBe` Right (int (-32768))
      binary (withOverflow Saturate) BPow (int 2) (int 15) `shouldBe` Right (int 32767)
    it "a huge exponent wraps to 0 for an even base" $
      binary (withOverflow Wrap) BPow (dint 2) (dint 1000000) `shouldBe` Right (dint 0)
    it "negative exponents: 1 / b^-e truncated" $ do
      binary p0 BPow (int 2) (int (-1)) `shouldBe` Right (int 0)
      binary p0 BPow (int (-1)) (int (-3)) `shouldBe` Right (int (-1))
      binary p0 BPow (int 1) (int (-5)) `shouldBe` Right (int 1)
      kindOf (binary p0 BPow (int 0) (int (-1))) `shouldBe` Just "division-by-zero"
    it "the exponent may have another integer type" $
      binary p0 BPow (dint 3) (usint 3) `shouldBe` Right (dint 27)
    it "REAL ** REAL in binary64, rounded to binary32" $
      binary p0 BPow (VReal 2) (VReal 0.5) `shouldBe` Right (VReal 1.4142135)
    it "REAL ** INT" $
      binary p0 BPow (VReal 1.5) (int 2) `shouldBe` Right (VReal 2.25)

  describe "comparisons (TC-OP-45..47)" $ do
    it "strings compare by character code: 'One' > 'ONE'" $
      binary p0 BGt (str "One") (str "ONE") `shouldBe` Right (VBool True)
    it "a proper prefix is smaller" $ do
      binary p0 BLt (str "ab") (str "abc") `shouldBe` Right (VBool True)
      binary p0 BLt (str "") (str "a") `shouldBe` Right (VBool True)
    it "bit strings compare as unsigned numbers" $
      binary p0 BGt (word 65535) (word 1) `shouldBe` Right (VBool True)
    it "FALSE < TRUE" $
      binary p0 BLt (VBool False) (VBool True) `shouldBe` Right (VBool True)
    it "enumerated values are equal by name" $ do
      binary p0 BEq (VEnum "Colour" "red") (VEnum "Colour" "red") `shouldBe` Right (VBool True)
      binary p0 BNe (VEnum "Colour" "red") (VEnum "Colour" "green") `shouldBe` Right (VBool True)

  describe "date and time arithmetic (Tab.3.20, TC-OP-49..62)" $ do
    it "TIME + TIME" $
      binary p0 BAdd (ms 1000) (ms 500) `shouldBe` Right (ms 1500)
    it "TIME overflow wraps in 32 bits under wrap" $
      binary (withOverflow Wrap) BAdd (ms 2147483647) (ms 1) `shouldBe` Right (ms (-2147483648))
    it "TOD + TIME wraps past midnight (TC-OP-60)" $
      binary p0 BAdd (VTod (23 * 3600000)) (ms (2 * 3600000)) `shouldBe` Right (VTod 3600000)
    it "TOD - TIME wraps before midnight" $
      binary p0 BSub (VTod 3600000) (ms (2 * 3600000)) `shouldBe` Right (VTod (23 * 3600000))
    it "TOD - TOD may be negative (TC-OP-61)" $
      binary p0 BSub (VTod 3600000) (VTod (23 * 3600000)) `shouldBe` Right (ms (-79200000))
    it "DATE - DATE is a TIME" $
      binary p0 BSub (VDate 86400000) (VDate 0) `shouldBe` Right (ms 86400000)
    it "DATE - DATE beyond the TIME range overflows (40 days)" $ do
      binary (withOverflow Wrap) BSub (VDate (40 * 86400000)) (VDate 0) `shouldBe` Right (ms (3456000000 - 4294967296))
      binary (withOverflow Saturate) BSub (VDate (40 * 86400000)) (VDate 0) `shouldBe` Right (ms 2147483647)
    it "DT + TIME, DT - DT" $ do
      binary p0 BAdd (VDT 0) (ms 3600000) `shouldBe` Right (VDT 3600000)
      binary p0 BSub (VDT 7200000) (VDT 3600000) `shouldBe` Right (ms 3600000)
    it "TIME * INT, TIME * REAL truncated (TC-OP-62)" $ do
      binary p0 BMul (ms 1000) (int 3) `shouldBe` Right (ms 3000)
      binary p0 BMul (ms 1000) (VReal 1.5) `shouldBe` Right (ms 1500)
      -- REAL 0.15 is 0.1500000059604645; 10 * that = 1.5000000596 -> 1
      binary p0 BMul (ms 10) (VReal 0.15) `shouldBe` Right (ms 1)
    it "TIME / n truncates toward zero, whatever mod-sign" $ do
      binary p0 BDiv (ms 10) (int 3) `shouldBe` Right (ms 3)
      binary p0 {pModSign = ModSignEuclidean} BDiv (ms (-10)) (int 3) `shouldBe` Right (ms (-3))
      binary p0 BDiv (ms 10) (VReal 4) `shouldBe` Right (ms 2)
    it "TIME / 0 follows div-zero" $ do
      kindOf (binary p0 BDiv (ms 10) (int 0)) `shouldBe` Just "division-by-zero"
      binary p0 {pDivZero = DivZeroZero} BDiv (ms 10) (int 0) `shouldBe` Right (ms 0)

  describe "typing of operators" $ do
    let ty = binaryType p0
    it "arithmetic on one ANY_NUM type" $ do
      ty BAdd (TElem INT) (TElem INT) `shouldBe` Right (TElem INT)
      ty BAdd (TElem INT) (TElem DINT) `shouldSatisfy` isLeft
      ty BAdd (TElem BOOL) (TElem BOOL) `shouldSatisfy` isLeft
      ty BAdd (TElem WORD) (TElem WORD) `shouldSatisfy` isLeft
      ty BAdd (TSubrange INT 0 10) (TElem INT) `shouldBe` Right (TElem INT)
    it "MOD also on REAL (TC-OP-11)" $
      ty BMod (TElem REAL) (TElem REAL) `shouldBe` Right (TElem REAL)
    it "** takes the base's type" $ do
      ty BPow (TElem REAL) (TElem INT) `shouldBe` Right (TElem REAL)
      ty BPow (TElem DINT) (TElem USINT) `shouldBe` Right (TElem DINT)
      ty BPow (TElem INT) (TElem REAL) `shouldSatisfy` isLeft
    it "Tab.3.20" $ do
      ty BAdd (TElem TOD) (TElem TIME) `shouldBe` Right (TElem TOD)
      ty BAdd (TElem TIME) (TElem TOD) `shouldSatisfy` isLeft
      ty BSub (TElem DATE) (TElem DATE) `shouldBe` Right (TElem TIME)
      ty BAdd (TElem DATE) (TElem DATE) `shouldSatisfy` isLeft
      ty BMul (TElem TIME) (TElem REAL) `shouldBe` Right (TElem TIME)
      ty BMul (TElem INT) (TElem TIME) `shouldSatisfy` isLeft
    it "STRING + STRING holds both (TC-OP-9)" $
      ty BAdd (TString False 10) (TString False 20) `shouldBe` Right (TString False 30)
    it "< not on enumerations, = on them (TC-TYPE-36)" $ do
      let e = TEnum "Colour" ["red", "green"]
      ty BLt e e `shouldSatisfy` isLeft
      ty BEq e e `shouldBe` Right (TElem BOOL)
    it "AND on one ANY_BIT type" $ do
      ty BAnd (TElem WORD) (TElem WORD) `shouldBe` Right (TElem WORD)
      ty BAnd (TElem INT) (TElem INT) `shouldSatisfy` isLeft
    it "unary operators" $ do
      unaryType UNeg (TElem UINT) `shouldSatisfy` isLeft
      unaryType UNeg (TElem TIME) `shouldBe` Right (TElem TIME)
      unaryType UNot (TElem INT) `shouldSatisfy` isLeft
      unaryType UNot (TElem BYTE) `shouldBe` Right (TElem BYTE)

  describe "bit strings (TC-OP-31..39)" $ do
    it "SHL, SHR fill with zeros" $ do
      call p0 "SHL" [byte 0x81, int 1] `shouldBe` Right (byte 0x02)
      call p0 "SHR" [byte 0x81, int 1] `shouldBe` Right (byte 0x40)
    it "ROL, ROR rotate" $ do
      call p0 "ROL" [byte 0x81, int 1] `shouldBe` Right (byte 0x03)
      call p0 "ROR" [byte 0x81, int 1] `shouldBe` Right (byte 0xC0)
    it "N >= width: shifts give 0, rotations go modulo the width" $ do
      call p0 "SHL" [word 1, int 16] `shouldBe` Right (word 0)
      call p0 "ROL" [byte 0x81, int 9] `shouldBe` Right (byte 0x03)
    it "a negative N counts as 0 (TC-OP-36)" $
      call p0 "SHL" [byte 1, int (-1)] `shouldBe` Right (byte 1)
    it "NOT, AND on WORD" $ do
      unary p0 UNot (word 0x00FF) `shouldBe` Right (word 0xFF00)
      binary p0 BAnd (word 0x0F0F) (word 0x00FF) `shouldBe` Right (word 0x000F)

  describe "string functions (TC-STR-1..19)" $ do
    it "INSERT at position P under insert-position=at (TC-STR-13)" $
      call p0 "INSERT" [str "First sentence", str " short", int 6] `shouldBe` Right (str "First short sentence")
    it "INSERT after the P-th character under insert-position=after (IEC)" $
      call p0 {pInsertPosition = InsertAfter} "INSERT" [str "First sentence", str " short", int 6] `shouldBe` Right (str "First  shortsentence")
    it "LEFT, RIGHT, MID" $ do
      call p0 "LEFT" [str "Hello", int 2] `shouldBe` Right (str "He")
      call p0 "RIGHT" [str "Hello", int 3] `shouldBe` Right (str "llo")
      call p0 "MID" [str "Hello", int 3, int 2] `shouldBe` Right (str "ell")
    it "positions and lengths are cut under string-bounds=clamp" $ do
      call p0 "LEFT" [str "Hello", int 10] `shouldBe` Right (str "Hello")
      call p0 "LEFT" [str "Hello", int (-1)] `shouldBe` Right (str "")
      call p0 "MID" [str "Hello", int 2, int 0] `shouldBe` Right (str "He")
      call p0 "MID" [str "Hello", int 2, int 7] `shouldBe` Right (str "")
    it "and are errors under string-bounds=error" $ do
      let strict = p0 {pStringBounds = StringBoundsError}
      kindOf (call strict "LEFT" [str "Hello", int 10]) `shouldBe` Just "index-out-of-range"
      kindOf (call strict "MID" [str "Hello", int 2, int 5]) `shouldBe` Just "index-out-of-range"
      call strict "MID" [str "Hello", int 1, int 5] `shouldBe` Right (str "o")
    it "DELETE, REPLACE" $ do
      call p0 "DELETE" [str "Hello", int 2, int 2] `shouldBe` Right (str "Hlo")
      call p0 "REPLACE" [str "Hello", str "XY", int 3, int 2] `shouldBe` Right (str "HXYo")
    it "FIND: first occurrence, 0 if none, case-sensitive" $ do
      call p0 "FIND" [str "abcabc", str "ca"] `shouldBe` Right (int 3)
      call p0 "FIND" [str "abc", str "x"] `shouldBe` Right (int 0)
      call p0 "FIND" [str "One", str "one"] `shouldBe` Right (int 0)
    it "LEN, CONCAT" $ do
      call p0 "LEN" [str "Hello"] `shouldBe` Right (int 5)
      call p0 "CONCAT" [str "a", str "b", str "c"] `shouldBe` Right (str "abc")
    it "typing: capacities, ANY_INT positions of any integer type" $ do
      standardType p0 "CONCAT" [TString False 10, TString False 20] `shouldBe` Just (Right (TString False 30))
      standardType p0 "LEFT" [TString False 10, TElem UINT] `shouldBe` Just (Right (TString False 10))
      fmap isLeft (standardType p0 "LEFT" [TString False 10, TElem REAL]) `shouldBe` Just True
      standardType p0 "FIND" [s255, s255] `shouldBe` Just (Right (TElem INT))
      standardType p0 "NO_SUCH_FUNCTION" [] `shouldBe` Nothing

  describe "other standard functions" $ do
    it "MAX, MIN, LIMIT (TC-OP-41, TC-OP-42, TC-OP-44)" $ do
      call p0 "MAX" [int 3, int 7, int 5] `shouldBe` Right (int 7)
      call p0 "MIN" [int 3, int 7, int 5] `shouldBe` Right (int 3)
      call p0 "LIMIT" [int 0, int 15, int 10] `shouldBe` Right (int 10)
      call p0 "LIMIT" [int 10, int 5, int 0] `shouldBe` Right (int 0)
    it "SEL, MUX" $ do
      call p0 "SEL" [VBool True, int 1, int 2] `shouldBe` Right (int 2)
      call p0 "MUX" [int 1, int 10, int 20, int 30] `shouldBe` Right (int 20)
    it "comparison chains (TC-OP-45)" $ do
      call p0 "GT" [int 3, int 2, int 1] `shouldBe` Right (VBool True)
      call p0 "GT" [int 3, int 2, int 2] `shouldBe` Right (VBool False)
    it "ADD is extensible" $
      call p0 "ADD" [int 1, int 2, int 3] `shouldBe` Right (int 6)
    it "ABS of the most negative integer follows overflow (TC-OP-30)" $ do
      call (withOverflow Wrap) "ABS" [int (-32768)] `shouldBe` Right (int (-32768))
      call (withOverflow Saturate) "ABS" [int (-32768)] `shouldBe` Right (int 32767)
    it "REAL functions" $ do
      call p0 "SQRT" [VReal 2] `shouldBe` Right (VReal 1.4142135)
      call p0 "LOG" [VLReal 1000] `shouldBe` Right (VLReal 3)
      call p0 "EXP" [VReal 100] `shouldBe` Right (VReal (1 / 0))
      call p0 {pRealOverflow = RealOverflowSaturate} "EXP" [VReal 100] `shouldBe` Right (VReal 3.4028235e38)
    it "typing: one type for all generic arguments (TC-CONV-1)" $ do
      fmap isLeft (standardType p0 "MAX" [TElem INT, TElem DINT]) `shouldBe` Just True
      standardType p0 "ADD" [TElem TOD, TElem TIME] `shouldBe` Just (Right (TElem TOD))
      standardType p0 "SHL" [TElem WORD, TElem USINT] `shouldBe` Just (Right (TElem WORD))

  describe "conversions (TC-CONV-6..18)" $ do
    let conv p from to = convert p (TElem from) (TElem to)
    it "names" $ do
      conversionName p0 "INT_TO_REAL" `shouldBe` Just (INT, REAL)
      conversionName p0 "DATE_AND_TIME_TO_TIME_OF_DAY" `shouldBe` Just (DT, TOD)
      conversionName p0 "dt_to_date" `shouldBe` Just (DT, DATE)
      conversionName p0 "TIME_TO_DINT" `shouldBe` Just (TIME, DINT)
      conversionName p0 "INT_TO_INT" `shouldBe` Nothing
      conversionName p0 "DATE_TO_INT" `shouldBe` Nothing
      conversionName p0 "STRING_TO_INT" `shouldBe` Nothing
      conversionFunction p0 "STRING_TO_INT" `shouldBe` Just (Convert CString (CElem INT))
      conversionFunction p0 "BCD_TO_INT" `shouldBe` Just (BcdToInt Nothing INT)
      conversionFunction p0 "INT_TO_BCD_WORD" `shouldBe` Just (IntToBcd INT (Just WORD))
    it "INT_TO_SINT(300) is 44 under narrow-int=wrap, 127 under saturate (TC-CONV-13)" $ do
      conv p0 INT SINT (int 300) `shouldBe` Right (sint 44)
      conv p0 {pNarrowInt = NarrowSaturate} INT SINT (int 300) `shouldBe` Right (sint 127)
    it "INT_TO_UINT(-1) is 65535 under wrap (TC-CONV-14)" $
      conv p0 INT UINT (int (-1)) `shouldBe` Right (VInt UINT 65535)
    it "REAL_TO_INT rounds half to even under round-even (TC-CONV-12)" $ do
      conv p0 REAL INT (VReal 2.5) `shouldBe` Right (int 2)
      conv p0 REAL INT (VReal 3.5) `shouldBe` Right (int 4)
      conv p0 REAL INT (VReal (-2.5)) `shouldBe` Right (int (-2))
    it "REAL_TO_INT truncates under truncate-saturate" $ do
      conv p0 {pRealToInt = TruncateSaturate} REAL INT (VReal 3.7) `shouldBe` Right (int 3)
      conv p0 {pRealToInt = TruncateSaturate} REAL INT (VReal (-3.7)) `shouldBe` Right (int (-3))
    it "REAL_TO_INT out of range, NaN, infinity" $ do
      conv p0 REAL INT (VReal 1.0e10) `shouldBe` Right (int 32767)
      conv p0 REAL INT (VReal (0 / 0)) `shouldBe` Right (int 0)
      conv p0 REAL INT (VReal (-1 / 0)) `shouldBe` Right (int (-32768))
      conv p0 {pRealToInt = RoundEvenWrap} REAL INT (VReal 65537) `shouldBe` Right (int 1)
    it "DINT_TO_REAL rounds to nearest, ties to even" $
      conv p0 DINT REAL (dint 16777217) `shouldBe` Right (VReal 16777216)
    it "LREAL_TO_REAL beyond the range follows real-overflow" $ do
      conv p0 LREAL REAL (VLReal 1.0e300) `shouldBe` Right (VReal (1 / 0))
      conv p0 {pRealOverflow = RealOverflowSaturate} LREAL REAL (VLReal 1.0e300) `shouldBe` Right (VReal 3.4028235e38)
    it "BOOL to and from numbers" $ do
      conv p0 BOOL INT (VBool True) `shouldBe` Right (int 1)
      conv p0 INT BOOL (int 5) `shouldBe` Right (VBool True)
      conv p0 INT BOOL (int 0) `shouldBe` Right (VBool False)
    it "TIME in milliseconds (TC-CONV-16)" $ do
      conv p0 TIME DINT (ms 1000) `shouldBe` Right (dint 1000)
      conv p0 DINT TIME (dint 1500) `shouldBe` Right (ms 1500)
    it "DT_TO_TOD, DT_TO_DATE (TC-CONV-10)" $ do
      conv p0 DT TOD (VDT (86400000 + 3600000)) `shouldBe` Right (VTod 3600000)
      conv p0 DT DATE (VDT (86400000 + 3600000)) `shouldBe` Right (VDate 86400000)
    it "BCD (TC-CONV-8, TC-CONV-9, TC-CONV-15)" $ do
      conversion p0 "BCD_TO_INT" [TElem WORD] [word 0x1234] `shouldBe` Right (int 1234)
      conversion p0 "INT_TO_BCD" [TElem INT] [int 1234] `shouldBe` Right (word 0x1234)
      kindOf (conversion p0 "BCD_TO_INT" [TElem WORD] [word 0x12A4]) `shouldBe` Just "conversion"
      kindOf (conversion p0 "INT_TO_BCD" [TElem INT] [int (-1)]) `shouldBe` Just "conversion"
    it "TRUNC gives DINT toward zero (TC-CONV-7)" $ do
      conversion p0 "TRUNC" [TElem REAL] [VReal (-2.7)] `shouldBe` Right (dint (-2))
      conversionType p0 "TRUNC" [TElem LREAL] `shouldBe` Just (Right (TElem DINT))
    it "to STRING (TC-CONV-17)" $ do
      convert p0 (TElem INT) s255 (int (-42)) `shouldBe` Right (str "-42")
      convert p0 (TElem REAL) s255 (VReal 0.1) `shouldBe` Right (str "0.1")
      convert p0 (TElem REAL) s255 (VReal 1.0e10) `shouldBe` Right (str "1.0E+10")
      convert p0 (TElem LREAL) s255 (VLReal 100) `shouldBe` Right (str "100.0")
      convert p0 (TElem TIME) s255 (ms 90000) `shouldBe` Right (str "T#1m30s")
      convert p0 (TElem BOOL) s255 (VBool True) `shouldBe` Right (str "TRUE")
    it "from STRING (TC-CONV-17): invalid text gives 0" $ do
      convert p0 s255 (TElem INT) (str "123") `shouldBe` Right (int 123)
      convert p0 s255 (TElem INT) (str " -7 ") `shouldBe` Right (int (-7))
      convert p0 s255 (TElem INT) (str "12a") `shouldBe` Right (int 0)
      convert p0 s255 (TElem WORD) (str "16#FF") `shouldBe` Right (word 255)
      convert p0 s255 (TElem REAL) (str "2.5") `shouldBe` Right (VReal 2.5)
      convert p0 s255 (TElem REAL) (str "1.5E-3") `shouldBe` Right (VReal 0.0015)
    it "typing of conversion calls" $ do
      standardType p0 "INT_TO_STRING" [TElem INT] `shouldBe` Just (Right (TString False 255))
      fmap isLeft (standardType p0 "INT_TO_REAL" [TElem DINT]) `shouldBe` Just True
