-- | Conversions (catalogue §3, Table 4-6 rows C01-C53, MT-CONV-7..10, A8)
-- under the real-to-int and narrow-int policies. Expected values are
-- computed by hand from the "formal" column.
module ConversionsSpec (spec) where

import Data.Int (Int16, Int32)
import Data.List (nub, sort)
import Data.Word (Word16, Word32, Word8)
import Stref.Conversions
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec
import Test.QuickCheck

mt :: Policies
mt = mastertoolXE

narrowSat :: Policies
narrowSat = mt {pNarrowInt = NarrowSaturate}

roundSat, roundWrap :: Policies
roundSat = mt {pRealToInt = RoundEvenSaturate}
roundWrap = mt {pRealToInt = RoundEvenWrap}

bitsR :: Word32 -> Value
bitsR = VReal . realFromBits

nan, posInf, negInf :: Float
nan = realFromBits 0x7FC00000
posInf = realFromBits 0x7F800000
negInf = realFromBits 0xFF800000

-- | (row, argument, target, expected) under the MasterTool preset.
rowCases :: [(Int, Value, BasicType, Value)]
rowCases =
  [ (1, VBool True, BYTE, VByte 1)
  , (1, VBool False, BYTE, VByte 0)
  , (2, VBool True, WORD, VWord 1)
  , (3, VBool True, DWORD, VDWord 1)
  , (4, VBool True, USINT, VUSInt 1)
  , (4, VBool False, USINT, VUSInt 0)
  , (5, VBool True, INT, VInt 1)
  , (6, VBool True, DINT, VDInt 1)
  , (7, VBool True, REAL, VReal 1)
  , (7, VBool False, REAL, bitsR 0)
  , (8, VByte 0, BOOL, VBool False)
  , (8, VByte 0x80, BOOL, VBool True)
  , (9, VByte 0xFF, USINT, VUSInt 255)
  , (10, VByte 0xFF, WORD, VWord 0x00FF)
  , (11, VByte 0x80, DWORD, VDWord 0x00000080)
  , (12, VByte 0xFF, INT, VInt 255) -- the value, not -1 (MT-CONV-10)
  , (13, VByte 0xFF, DINT, VDInt 255)
  , (14, VByte 0xFF, REAL, VReal 255)
  , (15, VWord 0x0100, BOOL, VBool True) -- low byte zero, the word is not
  , (15, VWord 0, BOOL, VBool False)
  , (16, VWord 0x1234, BYTE, VByte 0x34)
  , (17, VWord 0xFFFE, USINT, VUSInt 254)
  , (18, VWord 0x8000, INT, VInt (-32768))
  , (18, VWord 0xFFFF, INT, VInt (-1))
  , (18, VWord 0x7FFF, INT, VInt 32767)
  , (19, VWord 0xFFFF, DWORD, VDWord 0x0000FFFF)
  , (20, VWord 0xFFFF, DINT, VDInt 65535)
  , (21, VWord 0xFFFF, REAL, VReal 65535)
  , (22, VDWord 0x80000000, BOOL, VBool True)
  , (22, VDWord 0, BOOL, VBool False)
  , (23, VDWord 0x12345678, BYTE, VByte 0x78)
  , (24, VDWord 0x000001FF, USINT, VUSInt 255)
  , (24, VDWord 0x00000100, USINT, VUSInt 0)
  , (25, VDWord 0x12345678, WORD, VWord 0x5678)
  , (26, VDWord 0x00018000, INT, VInt (-32768)) -- low word 16#8000
  , (26, VDWord 0xFFFFFFFF, INT, VInt (-1))
  , (27, VDWord 0xFFFFFFFF, DINT, VDInt (-1))
  , (27, VDWord 0x80000000, DINT, VDInt (-2147483648))
  , -- 4294967295 = 2^32 - 1; the binary32 neighbours are 2^32 - 256 and 2^32.
    (28, VDWord 0xFFFFFFFF, REAL, VReal 4294967296)
  , (28, VDWord 16777215, REAL, VReal 16777215) -- the last exact one (MT: > 16777215 loses)
  , (28, VDWord 16777217, REAL, VReal 16777216) -- a tie, to the even significand
  , (29, VUSInt 0, BOOL, VBool False)
  , (29, VUSInt 1, BOOL, VBool True)
  , (30, VUSInt 200, BYTE, VByte 0xC8)
  , (31, VUSInt 255, WORD, VWord 0x00FF)
  , (32, VUSInt 255, DWORD, VDWord 0x000000FF)
  , (33, VUSInt 255, INT, VInt 255)
  , (34, VUSInt 255, DINT, VDInt 255)
  , (35, VUSInt 255, REAL, VReal 255)
  , (36, VInt (-1), BOOL, VBool True)
  , (36, VInt 0, BOOL, VBool False)
  , (37, VInt (-1), BYTE, VByte 0xFF)
  , (37, VInt 256, BYTE, VByte 0)
  , (37, VInt 0x1234, BYTE, VByte 0x34)
  , (38, VInt (-1), USINT, VUSInt 255)
  , (38, VInt 300, USINT, VUSInt 44) -- 300 - 256
  , (39, VInt (-1), WORD, VWord 0xFFFF)
  , (39, VInt (-32768), WORD, VWord 0x8000)
  , (40, VInt (-2), DWORD, VDWord 0xFFFFFFFE) -- sign-extended
  , (40, VInt 32767, DWORD, VDWord 0x00007FFF)
  , (41, VInt (-32768), DINT, VDInt (-32768))
  , (42, VInt (-32768), REAL, VReal (-32768))
  , (43, VDInt 65536, BOOL, VBool True) -- low word zero, the value is not
  , (43, VDInt 0, BOOL, VBool False)
  , (44, VDInt (-1), BYTE, VByte 0xFF)
  , (44, VDInt 256, BYTE, VByte 0)
  , (45, VDInt 300, USINT, VUSInt 44)
  , (45, VDInt (-1), USINT, VUSInt 255)
  , (46, VDInt 70000, WORD, VWord 0x1170) -- 70000 - 65536 = 4464 = 16#1170
  , (46, VDInt (-1), WORD, VWord 0xFFFF)
  , (47, VDInt 70000, INT, VInt 4464) -- wraps, does not saturate
  , (47, VDInt (-70000), INT, VInt (-4464)) -- -70000 + 65536
  , (47, VDInt 32768, INT, VInt (-32768))
  , (48, VDInt (-1), DWORD, VDWord 0xFFFFFFFF)
  , (48, VDInt (-2147483648), DWORD, VDWord 0x80000000)
  , (49, VDInt 16777217, REAL, VReal 16777216) -- 2^24 + 1: tie, to even
  , -- 2^24 + 3: between 2^24 + 2 (significand 8388609, odd) and 2^24 + 4 (even)
    (49, VDInt (-16777219), REAL, VReal (-16777220))
  , (49, VDInt 2147483647, REAL, VReal 2147483648)
  , (50, VReal 0, BOOL, VBool False)
  , (50, VReal (-0.0), BOOL, VBool False)
  , (50, VReal 0.5, BOOL, VBool True)
  , (50, VReal nan, BOOL, VBool True) -- NaN is not zero
  , (51, VReal 70000.7, WORD, VWord 0x1170) -- DINT 70000, low word
  , (51, VReal (-1.5), WORD, VWord 0xFFFF) -- DINT -1
  , (51, VReal 1.0e10, WORD, VWord 0xFFFF) -- DINT saturates at 16#7FFF_FFFF
  , (52, VReal 40000, INT, VInt 32767)
  , (52, VReal (-40000), INT, VInt (-32768))
  , (52, VReal (-2.9), INT, VInt (-2)) -- the integer part, no rounding (MT-CONV-9)
  , (52, VReal 2.9, INT, VInt 2)
  , (52, VReal 32767.9, INT, VInt 32767)
  , (52, VReal (-32768.9), INT, VInt (-32768))
  , (52, VReal nan, INT, VInt 0)
  , (52, VReal posInf, INT, VInt 32767)
  , (52, VReal negInf, INT, VInt (-32768))
  , (53, VReal 3.0e9, DINT, VDInt 2147483647)
  , (53, VReal (-3.0e9), DINT, VDInt (-2147483648))
  , (53, VReal 2147483520, DINT, VDInt 2147483520) -- the last binary32 below 2^31
  , (53, VReal 2147483648, DINT, VDInt 2147483647) -- 2^31 saturates
  , (53, VReal (-2147483648), DINT, VDInt (-2147483648)) -- -2^31 fits
  , (53, VReal (-0.5), DINT, VDInt 0)
  , (53, VReal 1.0e30, DINT, VDInt 2147483647)
  ]

spec :: Spec
spec = do
  describe "Table 4-6 under the MasterTool preset" $ do
    it "the cases cover every row C01..C53, with the row's types" $ do
      sort (nub [n | (n, _, _, _) <- rowCases]) `shouldBe` [1 .. 53]
      [ (n, crFrom <$> row, crTo <$> row)
        | (n, v, t, _) <- rowCases
        , let row = conversionRow (valueType v) t
        , (crNumber <$> row) /= Just n
        ]
        `shouldBe` []
    mapM_
      ( \(n, v, t, expected) ->
          it (rowName n <> " " <> conversionLabel v t <> " " <> show v <> " = " <> show expected) $
            convert mt (valueType v) t v `shouldBe` expected
      )
      rowCases
  describe "identity" $
    it "T_TO_T returns the value unchanged (ANY_TO with the same type)" $
      map (\v -> convertAny mt (valueType v) v) [VInt (-5), VReal (-0.0), VDWord 7, VBool True]
        `shouldBe` [VInt (-5), VReal (-0.0), VDWord 7, VBool True]
  describe "ANY_TO for the pairs missing from Table 4-6 (A8, MT-CONV-7)" $ do
    it "REAL to BYTE goes through DINT: 300.7 -> 300 -> 16#2C; -1.0 -> 16#FF" $
      (convertAny mt BYTE (VReal 300.7), convertAny mt BYTE (VReal (-1)))
        `shouldBe` (VByte 0x2C, VByte 0xFF)
    it "REAL to USINT: 255.9 -> 255; 256.0 -> 0; -1.0 -> 255" $
      map (convertAny mt USINT . VReal) [255.9, 256, -1] `shouldBe` map VUSInt [255, 0, 255]
    it "REAL to DWORD: -1.0 -> 16#FFFF_FFFF; 3.0e9 saturates in DINT first -> 16#7FFF_FFFF" $
      (convertAny mt DWORD (VReal (-1)), convertAny mt DWORD (VReal 3.0e9))
        `shouldBe` (VDWord 0xFFFFFFFF, VDWord 0x7FFFFFFF)
    it "convert on such a pair means the same" $
      convert mt REAL BYTE (VReal 300.7) `shouldBe` VByte 0x2C
    it "the named functions do not exist" $
      map (fmap (const ()) . lookupConversionFunction) ["REAL_TO_BYTE", "REAL_TO_USINT", "REAL_TO_DWORD", "ANY_TO_BYTE"]
        `shouldBe` [Nothing, Nothing, Nothing, Just ()]
  describe "narrow-int=saturate" $ do
    it "DINT_TO_INT 70000 -> 32767, -70000 -> -32768 (wrap: 4464, -4464)" $
      (convert narrowSat DINT INT (VDInt 70000), convert narrowSat DINT INT (VDInt (-70000)))
        `shouldBe` (VInt 32767, VInt (-32768))
    it "INT_TO_USINT -1 -> 0, INT_TO_BYTE 300 -> 16#FF" $
      (convert narrowSat INT USINT (VInt (-1)), convert narrowSat INT BYTE (VInt 300))
        `shouldBe` (VUSInt 0, VByte 0xFF)
    it "WORD_TO_BYTE 16#1234 -> 16#FF (the unsigned value clamped)" $
      convert narrowSat WORD BYTE (VWord 0x1234) `shouldBe` VByte 0xFF
    it "DWORD_TO_INT 16#FFFF_FFFF (4294967295 unsigned) -> 32767" $
      convert narrowSat DWORD INT (VDWord 0xFFFFFFFF) `shouldBe` VInt 32767
    it "same width is a reinterpretation either way: INT_TO_WORD -1 -> 16#FFFF, WORD_TO_INT 16#8000 -> -32768" $
      (convert narrowSat INT WORD (VInt (-1)), convert narrowSat WORD INT (VWord 0x8000))
        `shouldBe` (VWord 0xFFFF, VInt (-32768))
    it "widening is untouched: INT_TO_DWORD -2 -> 16#FFFF_FFFE" $
      convert narrowSat INT DWORD (VInt (-2)) `shouldBe` VDWord 0xFFFFFFFE
    it "REAL_TO_WORD 70000.7 -> DINT 70000 -> 16#FFFF; -1.5 -> -1 -> 16#0000" $
      (convert narrowSat REAL WORD (VReal 70000.7), convert narrowSat REAL WORD (VReal (-1.5)))
        `shouldBe` (VWord 0xFFFF, VWord 0)
  describe "real-to-int" $ do
    it "truncate-saturate: 2.5 -> 2, 3.5 -> 3, -2.5 -> -2, -2.9 -> -2" $
      map (convert mt REAL INT . VReal) [2.5, 3.5, -2.5, -2.9] `shouldBe` map VInt [2, 3, -2, -2]
    it "round-even-saturate: 2.5 -> 2, 3.5 -> 4, -2.5 -> -2, -2.9 -> -3, 0.5 -> 0, 1.5 -> 2" $
      map (convert roundSat REAL INT . VReal) [2.5, 3.5, -2.5, -2.9, 0.5, 1.5] `shouldBe` map VInt [2, 4, -2, -3, 0, 2]
    it "round-even-saturate: 40000.0 -> 32767, 32767.5 -> 32768 -> 32767, +inf -> 32767" $
      map (convert roundSat REAL INT . VReal) [40000, 32767.5, posInf] `shouldBe` map VInt [32767, 32767, 32767]
    it "round-even-wrap: 40000.0 -> 40000 - 65536 = -25536; 32767.5 -> 32768 -> -32768" $
      map (convert roundWrap REAL INT . VReal) [40000, 32767.5] `shouldBe` map VInt [-25536, -32768]
    it "round-even-wrap: REAL_TO_DINT 3.0e9 -> 3000000000 - 2^32 = -1294967296" $
      convert roundWrap REAL DINT (VReal 3.0e9) `shouldBe` VDInt (-1294967296)
    it "round-even-wrap: infinities and NaN give 0" $
      map (convert roundWrap REAL DINT . VReal) [posInf, negInf, nan] `shouldBe` map VDInt [0, 0, 0]
    it "every alternative: NaN gives 0" $
      [convert p REAL INT (VReal nan) | p <- [mt, roundSat, roundWrap]] `shouldBe` replicate 3 (VInt 0)
    it "round-even-wrap composes in C51: REAL_TO_WORD 70000.5 -> 70000 (tie, even) -> 16#1170" $
      convert roundWrap REAL WORD (VReal 70000.5) `shouldBe` VWord 0x1170
  describe "laws" $ do
    it "INT_TO_WORD then WORD_TO_INT is the identity (every narrow-int)" $
      property $ \(x :: Int16) ->
        conjoin [convert p WORD INT (convert p INT WORD (VInt x)) === VInt x | p <- [mt, narrowSat]]
    it "WORD_TO_INT then INT_TO_WORD is the identity" $
      property $ \(x :: Word16) -> convert mt INT WORD (convert mt WORD INT (VWord x)) === VWord x
    it "DINT_TO_DWORD then DWORD_TO_DINT is the identity" $
      property $ \(x :: Int32) -> convert mt DWORD DINT (convert mt DINT DWORD (VDInt x)) === VDInt x
    it "widening then narrowing is the identity (every narrow-int)" $
      property $ forAll genWidening $ \(v, wide) ->
        conjoin [convert p wide (valueType v) (convert p (valueType v) wide v) === v | p <- [mt, narrowSat]]
    it "INT_TO_DWORD then DWORD_TO_INT is the identity under narrow-int=wrap" $
      property $ \(x :: Int16) -> convert mt DWORD INT (convert mt INT DWORD (VInt x)) === VInt x
    it "INT_TO_REAL then REAL_TO_INT is the identity (every real-to-int)" $
      property $ \(x :: Int16) ->
        conjoin [convert p REAL INT (convert p INT REAL (VInt x)) === VInt x | p <- [mt, roundSat, roundWrap]]
    it "DINT_TO_REAL is exact up to 2^24" $
      property $ forAll (choose (-16777216, 16777216)) $ \(x :: Int32) ->
        convert mt REAL DINT (convert mt DINT REAL (VDInt x)) === VDInt x
    it "REAL_TO_DINT truncates: in range, |r - result| < 1 and |result| <= |r|" $
      property $ forAll (choose (-2.0e9, 2.0e9)) $ \(x :: Float) ->
        case convert mt REAL DINT (VReal x) of
          VDInt n ->
            let q = toRational x; m = toRational n
             in abs (q - m) < 1 .&&. abs m <= abs q
          other -> counterexample (show other) False
    it "narrowing under wrap keeps the low bits: (result - value) is a multiple of 2^n" $
      property $ \(x :: Int32) ->
        case (convert mt DINT INT (VDInt x), convert mt DINT USINT (VDInt x)) of
          (VInt a, VUSInt b) ->
            (toInteger a - toInteger x) `mod` 65536 === 0 .&&. (toInteger b - toInteger x) `mod` 256 === 0
          other -> counterexample (show other) False
  where
    rowName n = "C" <> (if n < 10 then "0" else "") <> show n
    conversionLabel v t = show (valueType v) <> "_TO_" <> show t

-- | A value and a wider type of the same family that holds all its values.
genWidening :: Gen (Value, BasicType)
genWidening =
  oneof
    [ (,INT) . VUSInt <$> arbitrary
    , (,DINT) . VUSInt <$> arbitrary
    , (,DINT) . VInt <$> arbitrary
    , (,REAL) . VInt <$> arbitrary
    , (,WORD) . VByte <$> arbitrary
    , (,DWORD) . VByte <$> arbitrary
    , (,DWORD) . VWord <$> arbitrary
    , (,INT) . VByte <$> arbitrary
    , (,DINT) . VWord <$> arbitrary
    , (,WORD) . (VUSInt :: Word8 -> Value) <$> arbitrary
    ]
