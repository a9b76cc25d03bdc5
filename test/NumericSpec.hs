-- | Correctly rounded binary32 literals and the admissible ranges of integer
-- literals (MT-CONST-2, Table 4-15).
module NumericSpec (spec) where

import Data.Ratio ((%))
import Data.Word (Word32)
import Stref.Numeric
import Stref.Types
import Stref.Values (realBits, realFromBits)
import Test.Hspec
import Test.QuickCheck

bitsOf :: Rational -> Word32
bitsOf = realBits . realLiteral

spec :: Spec
spec = do
  describe "binary32 classes (IEEE 754 encodings: exponent all ones)" $ do
    it "the largest finite binary32 is 16#7F7FFFFF" $ realBits realMax `shouldBe` 0x7F7FFFFF
    it "the infinities are 16#7F800000 and 16#FF800000, nothing else" $
      property $ \(w :: Word32) ->
        isRealInfinite (realFromBits w) === (w == 0x7F800000 || w == 0xFF800000)
    it "NaN is an all-ones exponent with a nonzero significand" $
      property $ \(w :: Word32) ->
        isRealNaN (realFromBits w) === (w `mod` 0x80000000 > 0x7F800000)
    it "the edge patterns: 16#7F7FFFFF finite, 16#7F800000 infinite, 16#7F800001 and 16#FFC00000 NaN" $
      map (\w -> (isRealInfinite (realFromBits w), isRealNaN (realFromBits w))) [0x7F7FFFFF, 0x7F800000, 0x7F800001, 0xFFC00000]
        `shouldBe` [(False, False), (True, False), (False, True), (False, True)]
  describe "realLiteral: nearest binary32, ties to even" $ do
    -- 1254.4879 lies in [1024, 2048), spacing 2^-13: 1254.4879 * 8192 =
    -- 10276764.88..., rounded to 10276765 = 1254.4879150390625 * 8192;
    -- pattern (149 - 13) * 2^23 + 10276765 = 1151127453 = 16#449CCF9D.
    it "1254.4879 is 1254.4879150390625 (16#449CCF9D)" $ do
      bitsOf (12544879 % 10000) `shouldBe` 0x449CCF9D
      toRational (realLiteral (12544879 % 10000)) `shouldBe` 10276765 % 8192
    it "0.1 is 16#3DCCCCCD, -0.1 is 16#BDCCCCCD" $
      (bitsOf (1 % 10), bitsOf (-1 % 10)) `shouldBe` (0x3DCCCCCD, 0xBDCCCCCD)
    it "1.0e38 is 16#7E967699" $ bitsOf (10 ^ (38 :: Int)) `shouldBe` 0x7E967699
    it "exact values stay exact: 0, 1, -2, 0.5, 16777215" $
      map bitsOf [0, 1, -2, 1 % 2, 16777215] `shouldBe` [0, 0x3F800000, 0xC0000000, 0x3F000000, 0x4B7FFFFF]
    it "ties go to the even significand: 16777217 -> 16777216, 16777219 -> 16777220" $
      map (toRational . realLiteral) [16777217, 16777219] `shouldBe` [16777216, 16777220]
    it "just above a tie rounds up: 16777217 + 1/1000 -> 16777218" $
      toRational (realLiteral (16777217 + 1 % 1000)) `shouldBe` 16777218
    it "3.4028235e38 is FLT_MAX (16#7F7FFFFF)" $
      bitsOf (34028235 * 10 ^ (31 :: Int)) `shouldBe` 0x7F7FFFFF
    -- FLT_MAX = 2^128 - 2^104; halfway to 2^128 is 2^128 - 2^103, a tie whose
    -- even neighbour is 2^128: infinity.
    it "2^128 - 2^103 rounds to infinity, one less to FLT_MAX" $
      (bitsOf (2 ^ (128 :: Int) - 2 ^ (103 :: Int)), bitsOf (2 ^ (128 :: Int) - 2 ^ (103 :: Int) - 1))
        `shouldBe` (0x7F800000, 0x7F7FFFFF)
    it "subnormals: 2^-149 is 16#00000001, 2^-150 (a tie) is 0, 3 * 2^-151 is 2^-149" $
      map bitsOf [1 % 2 ^ (149 :: Int), 1 % 2 ^ (150 :: Int), 3 % 2 ^ (151 :: Int)] `shouldBe` [1, 0, 1]
    it "1.0e-45 is the smallest subnormal (1.4e-45)" $ bitsOf (1 % 10 ^ (45 :: Int)) `shouldBe` 1
    it "the smallest normal 2^-126 is 16#00800000" $ bitsOf (1 % 2 ^ (126 :: Int)) `shouldBe` 0x00800000
    it "a negative value too small for binary32 becomes -0.0" $
      bitsOf (-1 % 2 ^ (151 :: Int)) `shouldBe` 0x80000000
    it "agrees with GHC's fromRational for Float (an independent implementation)" $
      property $ forAll genRational $ \q -> realBits (realLiteral q) === realBits (fromRational q)
    it "reads every finite binary32 back exactly" $
      property $ \(w :: Word32) ->
        let x = realFromBits w
         in not (isNaN x || isInfinite x) ==> realBits (realLiteral (toRational x)) === w
  describe "integerLiteralFits (Table 4-15)" $ do
    it "0..255 fit every integer type" $
      [t | t <- [USINT, INT, DINT, BYTE, WORD, DWORD], not (integerLiteralFits t 255)] `shouldBe` []
    it "256 does not fit USINT or BYTE" $
      map (`integerLiteralFits` 256) [USINT, BYTE, INT] `shouldBe` [False, False, True]
    it "-1 fits INT and DINT only" $
      filter (`integerLiteralFits` (-1)) [USINT, BYTE, WORD, DWORD, INT, DINT] `shouldBe` [INT, DINT]
    it "16#8000 = 32768 is not an INT literal, but DINT, WORD, DWORD (MT-CONST-6)" $
      filter (`integerLiteralFits` 32768) [USINT, BYTE, INT, WORD, DINT, DWORD] `shouldBe` [WORD, DINT, DWORD]
    it "-32768 fits INT, -32769 does not" $
      (integerLiteralFits INT (-32768), integerLiteralFits INT (-32769)) `shouldBe` (True, False)
    it "65535 fits WORD, 65536 does not" $
      (integerLiteralFits WORD 65535, integerLiteralFits WORD 65536) `shouldBe` (True, False)
    it "DINT: -2147483648..2147483647" $
      map (integerLiteralFits DINT) [-2147483648, 2147483647, 2147483648, -2147483649]
        `shouldBe` [True, True, False, False]
    it "16#FFFF_FFFF is DWORD only; 4294967296 fits nothing" $
      ( filter (`integerLiteralFits` 4294967295) [DINT, DWORD]
      , filter (`integerLiteralFits` 4294967296) allBasicTypes
      )
        `shouldBe` ([DWORD], [])
    it "BOOL: only 0 and 1" $
      map (integerLiteralFits BOOL) [0, 1, 2, -1] `shouldBe` [True, True, False, False]
    it "REAL: integer literals of the INT range (MT-CONST-4, A10)" $
      map (integerLiteralFits REAL) [0, 32767, -32768, 32768] `shouldBe` [True, True, True, False]
  describe "wrapTo and clampTo" $ do
    it "wrapTo INT 40000 = -25536, wrapTo USINT -1 = 255, wrapTo DWORD -1 = 4294967295" $
      (wrapTo INT 40000, wrapTo USINT (-1), wrapTo DWORD (-1)) `shouldBe` (-25536, 255, 4294967295)
    it "clampTo INT 40000 = 32767, clampTo USINT -1 = 0" $
      (clampTo INT 40000, clampTo USINT (-1)) `shouldBe` (32767, 0)

-- | Rationals across the binary32 range: decimal-looking values, values near
-- powers of two, ties, subnormals and overflows.
genRational :: Gen Rational
genRational =
  oneof
    [ (%) <$> arbitrary <*> (arbitrary `suchThat` (/= 0))
    , do
        m <- choose (-(2 ^ (30 :: Int)), 2 ^ (30 :: Int) :: Integer)
        e <- choose (-160, 135 :: Int)
        pure (toRational m * 2 ^^ e)
    , do
        m <- choose (1, 99999999 :: Integer)
        e <- choose (-50, 40 :: Int)
        pure (toRational m * 10 ^^ e)
    ]
