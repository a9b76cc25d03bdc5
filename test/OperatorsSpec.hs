-- | Operators on values (catalogue §5, decisions A5-A7) under every
-- alternative of the numeric policies. Expected values are computed by hand;
-- the derivation is next to the cases where it is not obvious.
module OperatorsSpec (spec) where

import Data.Int (Int16, Int32)
import Data.Word (Word8)
import Stref.Checked (ArithOp (..), CmpOp (..), LogicOp (..))
import Stref.Diagnostics
import Stref.Numeric (roundToReal)
import Stref.Operators
import Stref.Policy
import Stref.Values
import Test.Hspec
import Test.QuickCheck

mt :: Policies
mt = mastertoolXE

wrapP, trapP, promote, promoteSat, euclid :: Policies
wrapP = mt {pOverflow = Wrap}
trapP = mt {pOverflow = Trap}
promote = mt {pArithWidth = Promote32}
promoteSat = promote {pNarrowInt = NarrowSaturate}
euclid = mt {pModSign = ModSignEuclidean}

ieee :: Policies
ieee = mt {pRealOverflow = RealOverflowIeee, pRealDivZero = RealDivZeroIeee}

i :: Int16 -> Value
i = VInt

d :: Int32 -> Value
d = VDInt

u :: Word8 -> Value
u = VUSInt

r :: Float -> Value
r = VReal

bitsR :: Word -> Value
bitsR = VReal . realFromBits . fromIntegral

-- | binary32 constants by bit pattern.
fltMax, posInf, negInf, twoTo103, twoTo102 :: Float
fltMax = realFromBits 0x7F7FFFFF -- (2^24 - 1) * 2^104
posInf = realFromBits 0x7F800000
negInf = realFromBits 0xFF800000
twoTo103 = realFromBits 0x73000000 -- biased exponent 103 + 127 = 230
twoTo102 = realFromBits 0x72800000

nan :: Float
nan = realFromBits 0x7FC00000

isNaNValue :: Outcome -> Bool
isNaNValue = \case
  Right (VReal x, _) -> isNaN x
  _ -> False

spec :: Spec
spec = do
  integerArithmetic
  division
  promotion
  negation
  realArithmetic
  comparisons
  logicOps
  exptSpec
  laws

integerArithmetic :: Spec
integerArithmetic = describe "Operators: integer + - * (MT-OP-6, MT-OP-7)" $ do
  describe "overflow=saturate (MasterTool)" $ do
    it "INT 15000 + 25000 = 32767 with the flag (the manual's example)" $
      arith mt OpAdd (i 15000) (i 25000) `shouldBe` Right (i 32767, Just True)
    it "INT 15000 + 5000 = 20000, flag cleared" $
      arith mt OpAdd (i 15000) (i 5000) `shouldBe` Right (i 20000, Just False)
    it "INT 32767 + 0 stays in range: flag FALSE" $
      arith mt OpAdd (i 32767) (i 0) `shouldBe` Right (i 32767, Just False)
    it "INT -20000 + -20000 = -32768 with the flag" $
      arith mt OpAdd (i (-20000)) (i (-20000)) `shouldBe` Right (i (-32768), Just True)
    it "INT -32767 - 1 = -32768 exactly, flag FALSE" $
      arith mt OpSub (i (-32767)) (i 1) `shouldBe` Right (i (-32768), Just False)
    it "USINT 5 - 10 = 0 with the flag" $
      arith mt OpSub (u 5) (u 10) `shouldBe` Right (u 0, Just True)
    it "USINT 15 * 17 = 255 exactly, flag FALSE" $
      arith mt OpMul (u 15) (u 17) `shouldBe` Right (u 255, Just False)
    it "USINT 16 * 16 = 256 saturates to 255" $
      arith mt OpMul (u 16) (u 16) `shouldBe` Right (u 255, Just True)
    it "USINT 200 + 100 saturates to 255" $
      arith mt OpAdd (u 200) (u 100) `shouldBe` Right (u 255, Just True)
    it "INT 200 * 200 = 40000 saturates to 32767" $
      arith mt OpMul (i 200) (i 200) `shouldBe` Right (i 32767, Just True)
    it "INT -200 * 200 = -40000 saturates to -32768" $
      arith mt OpMul (i (-200)) (i 200) `shouldBe` Right (i (-32768), Just True)
    it "DINT 2147483647 + 1 saturates" $
      arith mt OpAdd (d 2147483647) (d 1) `shouldBe` Right (d 2147483647, Just True)
    it "DINT -2147483648 - 1 saturates" $
      arith mt OpSub (d (-2147483648)) (d 1) `shouldBe` Right (d (-2147483648), Just True)
    it "DINT 65536 * 65536 saturates" $
      arith mt OpMul (d 65536) (d 65536) `shouldBe` Right (d 2147483647, Just True)
  describe "overflow=wrap" $ do
    it "INT 15000 + 25000 = 40000 - 65536 = -25536, flag TRUE" $
      arith wrapP OpAdd (i 15000) (i 25000) `shouldBe` Right (i (-25536), Just True)
    it "USINT 5 - 10 = 251 (256 - 5), flag TRUE" $
      arith wrapP OpSub (u 5) (u 10) `shouldBe` Right (u 251, Just True)
    it "DINT 2147483647 + 1 = -2147483648, flag TRUE" $
      arith wrapP OpAdd (d 2147483647) (d 1) `shouldBe` Right (d (-2147483648), Just True)
    it "INT 200 * 200 = -25536, flag TRUE" $
      arith wrapP OpMul (i 200) (i 200) `shouldBe` Right (i (-25536), Just True)
    it "no overflow: flag FALSE" $
      arith wrapP OpAdd (i 1) (i 2) `shouldBe` Right (i 3, Just False)
  describe "overflow=trap" $ do
    it "INT 15000 + 25000 traps" $
      arith trapP OpAdd (i 15000) (i 25000) `shouldBe` Left trapOverflow
    it "USINT 5 - 10 traps" $
      arith trapP OpSub (u 5) (u 10) `shouldBe` Left trapOverflow
    it "in range: a value, flag FALSE" $
      arith trapP OpMul (i 100) (i 300) `shouldBe` Right (i 30000, Just False)
  it "operands of different types are an internal error, not a crash" $
    arith mt OpAdd (i 1) (d 1) `shouldBe` Left errOperandTypes
  it "arithmetic on BOOL or bit strings is an internal error (MT-TYPE-6)" $
    arith mt OpAdd (VWord 1) (VWord 1) `shouldBe` Left errOperandTypes

division :: Spec
division = describe "Operators: / and MOD (MT-OP-8..10, A7)" $ do
  describe "mod-sign=dividend (truncating division)" $ do
    it "7 / 2 = 3; -7 / 2 = -3; 7 / -2 = -3; -7 / -2 = 3" $
      map (\(a, b) -> arith mt OpDiv (i a) (i b)) [(7, 2), (-7, 2), (7, -2), (-7, -2)]
        `shouldBe` map (\q -> Right (i q, Nothing)) [3, -3, -3, 3]
    it "7 MOD 2 = 1; -7 MOD 2 = -1; 7 MOD -2 = 1; -7 MOD -2 = -1" $
      map (\(a, b) -> arith mt OpMod (i a) (i b)) [(7, 2), (-7, 2), (7, -2), (-7, -2)]
        `shouldBe` map (\q -> Right (i q, Nothing)) [1, -1, 1, -1]
    it "100 / 10 / 5 = 2 (MT-OP-17)" $
      (arith mt OpDiv (i 100) (i 10) >>= \(q, _) -> arith mt OpDiv q (i 5)) `shouldBe` Right (i 2, Nothing)
  describe "mod-sign=euclidean" $ do
    -- -7 = 2 * -4 + 1; 7 = -2 * -3 + 1; -7 = -2 * 4 + 1
    it "-7 / 2 = -4; 7 / -2 = -3; -7 / -2 = 4" $
      map (\(a, b) -> arith euclid OpDiv (d a) (d b)) [(-7, 2), (7, -2), (-7, -2)]
        `shouldBe` map (\q -> Right (d q, Nothing)) [-4, -3, 4]
    it "-7 MOD 2 = 1; 7 MOD -2 = 1; -7 MOD -2 = 1" $
      map (\(a, b) -> arith euclid OpMod (d a) (d b)) [(-7, 2), (7, -2), (-7, -2)]
        `shouldBe` map (\q -> Right (d q, Nothing)) [1, 1, 1]
    it "positive operands: the same as truncation (7 / 2 = 3, 7 MOD 2 = 1)" $
      (arith euclid OpDiv (i 7) (i 2), arith euclid OpMod (i 7) (i 2))
        `shouldBe` (Right (i 3, Nothing), Right (i 1, Nothing))
  describe "div-zero" $ do
    it "error: runtime error 2020 (MT-OP-9)" $
      arith mt OpDiv (i 5) (i 0) `shouldBe` Left errDivisionByZero
    it "error: 2020 for USINT and DINT too" $
      (arith mt OpDiv (u 5) (u 0), arith mt OpDiv (d 5) (d 0))
        `shouldBe` (Left errDivisionByZero, Left errDivisionByZero)
    it "zero: the result is 0, flag untouched" $
      arith mt {pDivZero = DivZeroZero} OpDiv (i 5) (i 0) `shouldBe` Right (i 0, Nothing)
    it "trap: the trap code" $
      arith mt {pDivZero = DivZeroTrap} OpDiv (d 5) (d 0) `shouldBe` Left trapDivisionByZero
  describe "mod-zero" $ do
    it "zero: x MOD 0 = 0, no error (MT-OP-8)" $
      arith mt OpMod (i 5) (i 0) `shouldBe` Right (i 0, Nothing)
    it "zero: USINT and DINT too" $
      (arith mt OpMod (u 9) (u 0), arith mt OpMod (d (-9)) (d 0))
        `shouldBe` (Right (u 0, Nothing), Right (d 0, Nothing))
    it "error: the mod-zero error code" $
      arith mt {pModZero = ModZeroError} OpMod (i 5) (i 0) `shouldBe` Left errModZero
    it "the div-zero policy does not affect MOD" $
      arith mt {pDivZero = DivZeroTrap} OpMod (i 5) (i 0) `shouldBe` Right (i 0, Nothing)
  describe "-32768 / -1 (A7): out of range, the flag is untouched" $ do
    it "saturate: 32767" $
      arith mt OpDiv (i (-32768)) (i (-1)) `shouldBe` Right (i 32767, Nothing)
    it "saturate: DINT -2147483648 / -1 = 2147483647" $
      arith mt OpDiv (d (-2147483648)) (d (-1)) `shouldBe` Right (d 2147483647, Nothing)
    it "wrap: -32768" $
      arith wrapP OpDiv (i (-32768)) (i (-1)) `shouldBe` Right (i (-32768), Nothing)
    it "trap: the overflow trap" $
      arith trapP OpDiv (i (-32768)) (i (-1)) `shouldBe` Left trapOverflow
    it "-32768 MOD -1 = 0, no overflow" $
      arith trapP OpMod (i (-32768)) (i (-1)) `shouldBe` Right (i 0, Nothing)
  it "MOD on REAL is an internal error (MT-OP-5)" $
    arith mt OpMod (r 5) (r 2) `shouldBe` Left errOperandTypes

promotion :: Spec
promotion = describe "Operators: arith-width=promote-32" $ do
  it "INT 15000 + 25000: 40000 fits 32 bits (flag FALSE), stored as -25536" $
    arith promote OpAdd (i 15000) (i 25000) `shouldBe` Right (i (-25536), Just False)
  it "with narrow-int=saturate the store clamps: 32767, flag FALSE" $
    arith promoteSat OpAdd (i 15000) (i 25000) `shouldBe` Right (i 32767, Just False)
  it "USINT 5 - 10 = -5 in 32 bits, stored as 251 (wrap) or 0 (saturate), flag FALSE" $
    (arith promote OpSub (u 5) (u 10), arith promoteSat OpSub (u 5) (u 10))
      `shouldBe` (Right (u 251, Just False), Right (u 0, Just False))
  it "DINT is already 32 bits: the overflow policy applies as usual" $
    arith promote OpAdd (d 2147483647) (d 1) `shouldBe` Right (d 2147483647, Just True)
  it "INT -32768 / -1 = 32768 in 32 bits, stored as -32768" $
    arith promote OpDiv (i (-32768)) (i (-1)) `shouldBe` Right (i (-32768), Nothing)
  it "in range: the same as operand-type" $
    arith promote OpMul (i 100) (i (-300)) `shouldBe` Right (i (-30000), Just False)

negation :: Spec
negation = describe "Operators: unary minus (MT-OP-4, MT-OP-5)" $ do
  it "-(5) = -5, flag FALSE" $
    negateValue mt (i 5) `shouldBe` Right (i (-5), Just False)
  it "-(-32768) = 32767 with the flag under saturate (MT-OP-6)" $
    negateValue mt (i (-32768)) `shouldBe` Right (i 32767, Just True)
  it "-(-2147483648) = 2147483647 with the flag" $
    negateValue mt (d (-2147483648)) `shouldBe` Right (d 2147483647, Just True)
  it "wrap: -(-32768) = -32768, flag TRUE" $
    negateValue wrapP (i (-32768)) `shouldBe` Right (i (-32768), Just True)
  it "trap: -(-32768) traps" $
    negateValue trapP (i (-32768)) `shouldBe` Left trapOverflow
  it "promote-32: -(-32768) = 32768 in 32 bits, stored as -32768, flag FALSE" $
    negateValue promote (i (-32768)) `shouldBe` Right (i (-32768), Just False)
  it "REAL: only the sign changes; -(0.0) is -0.0" $
    (negateValue mt (r 1.5), negateValue mt (r 0))
      `shouldBe` (Right (r (-1.5), Just False), Right (bitsR 0x80000000, Just False))
  it "USINT has no unary minus (MT-OP-5)" $
    negateValue mt (u 1) `shouldBe` Left errOperandTypes

realArithmetic :: Spec
realArithmetic = describe "Operators: REAL in binary32 (A6)" $ do
  it "16777216.0 + 1.0 = 16777216.0 (2^24 + 1 is a tie, to even)" $
    arith mt OpAdd (r 16777216) (r 1) `shouldBe` Right (r 16777216, Just False)
  -- 0.1 = 13421773 * 2^-27, 0.2 = 13421773 * 2^-26; the sum 40265319 * 2^-27
  -- lies in [0.25, 0.5) where the spacing is 2^-25: 40265319 / 4 = 10066329.75
  -- rounds to 10066330, pattern (149 - 25) * 2^23 + 10066330 = 0x3E99999A.
  it "0.1 + 0.2 has the pattern 16#3E99999A" $
    arith mt OpAdd (bitsR 0x3DCCCCCD) (bitsR 0x3E4CCCCD) `shouldBe` Right (bitsR 0x3E99999A, Just False)
  it "1.0 / 3.0 has the pattern 16#3EAAAAAB" $
    arith mt OpDiv (r 1) (r 3) `shouldBe` Right (bitsR 0x3EAAAAAB, Nothing)
  it "7.0 / 2.0 = 3.5 (no truncation for REAL)" $
    arith mt OpDiv (r 7) (r 2) `shouldBe` Right (r 3.5, Nothing)
  describe "real-overflow=saturate" $ do
    it "3.0e38 + 3.0e38 = 3.4028235e38 with the flag" $
      arith mt OpAdd (r 3.0e38) (r 3.0e38) `shouldBe` Right (r fltMax, Just True)
    it "-3.0e38 - 3.0e38 = -3.4028235e38 with the flag" $
      arith mt OpSub (r (-3.0e38)) (r 3.0e38) `shouldBe` Right (r (negate fltMax), Just True)
    it "1.0e20 * 1.0e20 saturates" $
      arith mt OpMul (r 1.0e20) (r (-1.0e20)) `shouldBe` Right (r (negate fltMax), Just True)
    -- FLT_MAX + 2^103 = 2^128 - 2^103: a tie between FLT_MAX (odd) and 2^128
    -- (even), so it rounds to infinity: an overflow. FLT_MAX + 2^102 rounds
    -- back to FLT_MAX: no overflow. Same value, different flag.
    it "FLT_MAX + 2^103 overflows (tie to even is 2^128)" $
      arith mt OpAdd (r fltMax) (r twoTo103) `shouldBe` Right (r fltMax, Just True)
    it "FLT_MAX + 2^102 rounds to FLT_MAX without overflow" $
      arith mt OpAdd (r fltMax) (r twoTo102) `shouldBe` Right (r fltMax, Just False)
    it "underflow to 0.0 is not an overflow" $
      arith mt OpMul (r 1.0e-30) (r 1.0e-30) `shouldBe` Right (r 0, Just False)
    it "division overflow saturates, the flag is untouched" $
      arith mt OpDiv (r 1.0e38) (r 1.0e-10) `shouldBe` Right (r fltMax, Nothing)
    it "an infinite operand is propagated, not an overflow of this operation" $
      arith mt OpAdd (r posInf) (r 1) `shouldBe` Right (r posInf, Just False)
  describe "real-overflow=ieee" $ do
    it "3.0e38 + 3.0e38 = +inf, the flag still reports the overflow" $
      arith ieee OpAdd (r 3.0e38) (r 3.0e38) `shouldBe` Right (r posInf, Just True)
    it "1.0e38 / 1.0e-10 = +inf" $
      arith ieee OpDiv (r 1.0e38) (r 1.0e-10) `shouldBe` Right (r posInf, Nothing)
  describe "real-div-zero" $ do
    it "error: 1.0 / 0.0 is runtime error 2020" $
      arith mt OpDiv (r 1) (r 0) `shouldBe` Left errDivisionByZero
    it "error: also for -0.0 and for 0.0 / 0.0" $
      (arith mt OpDiv (r 1) (r (-0.0)), arith mt OpDiv (r 0) (r 0))
        `shouldBe` (Left errDivisionByZero, Left errDivisionByZero)
    it "ieee: 1.0 / 0.0 = +inf, -1.0 / 0.0 = -inf, 1.0 / -0.0 = -inf" $
      (arith ieee OpDiv (r 1) (r 0), arith ieee OpDiv (r (-1)) (r 0), arith ieee OpDiv (r 1) (r (-0.0)))
        `shouldBe` (Right (r posInf, Nothing), Right (r negInf, Nothing), Right (r negInf, Nothing))
    it "ieee: 0.0 / 0.0 is NaN" $
      arith ieee OpDiv (r 0) (r 0) `shouldSatisfy` isNaNValue
    it "ieee division by zero is not clamped by real-overflow=saturate" $
      arith mt {pRealDivZero = RealDivZeroIeee} OpDiv (r 1) (r 0) `shouldBe` Right (r posInf, Nothing)

comparisons :: Spec
comparisons = describe "Operators: comparisons (MT-OP-11)" $ do
  it "INT -1 < 0" $ compareValues OpLt (i (-1)) (i 0) `shouldBe` True
  it "DINT 5 >= 5 and 5 > 5 is FALSE" $
    (compareValues OpGe (d 5) (d 5), compareValues OpGt (d 5) (d 5)) `shouldBe` (True, False)
  it "WORD compares unsigned: 16#FFFF > 16#0001" $
    compareValues OpGt (VWord 0xFFFF) (VWord 1) `shouldBe` True
  it "DWORD 16#8000_0000 > 1" $
    compareValues OpGt (VDWord 0x80000000) (VDWord 1) `shouldBe` True
  it "BOOL: TRUE = TRUE, TRUE <> FALSE" $
    (compareValues OpEq (VBool True) (VBool True), compareValues OpNe (VBool True) (VBool False))
      `shouldBe` (True, True)
  it "REAL: -0.0 = 0.0" $ compareValues OpEq (r (-0.0)) (r 0) `shouldBe` True
  it "REAL: NaN is unordered: <, >, <=, >=, = are FALSE, <> is TRUE" $
    [compareValues op (r nan) (r 1) | op <- [OpLt, OpGt, OpLe, OpGe, OpEq, OpNe]]
      `shouldBe` [False, False, False, False, False, True]
  it "REAL: NaN = NaN is FALSE" $ compareValues OpEq (r nan) (r nan) `shouldBe` False
  it "REAL: 1.0 < 2.0, -inf < -3.4e38" $
    (compareValues OpLt (r 1) (r 2), compareValues OpLt (r negInf) (r (negate fltMax))) `shouldBe` (True, True)

logicOps :: Spec
logicOps = describe "Operators: logic and bitwise (MT-OP-12..14)" $ do
  it "Table 4-12 truth table for AND, OR, XOR" $
    [ (logic OpAnd (VBool a) (VBool b), logic OpOr (VBool a) (VBool b), logic OpXor (VBool a) (VBool b))
    | (a, b) <- [(False, False), (False, True), (True, False), (True, True)]
    ]
      `shouldBe` [ (VBool False, VBool False, VBool False)
                 , (VBool False, VBool True, VBool True)
                 , (VBool False, VBool True, VBool True)
                 , (VBool True, VBool True, VBool False)
                 ]
  it "BYTE 2#0011_1001 AND 2#0001_1100 = 2#0001_1000 (the manual's example)" $
    logic OpAnd (VByte 0x39) (VByte 0x1C) `shouldBe` VByte 0x18
  it "WORD 16#F0F0 OR 16#0F00 = 16#FFF0" $
    logic OpOr (VWord 0xF0F0) (VWord 0x0F00) `shouldBe` VWord 0xFFF0
  it "DWORD 16#FFFF_0000 XOR 16#0F0F_0F0F = 16#F0F0_0F0F" $
    logic OpXor (VDWord 0xFFFF0000) (VDWord 0x0F0F0F0F) `shouldBe` VDWord 0xF0F00F0F
  it "NOT: BOOL complement, bitwise on BYTE, WORD, DWORD" $
    map notValue [VBool True, VByte 0x0F, VWord 0x00FF, VDWord 0]
      `shouldBe` [VBool False, VByte 0xF0, VWord 0xFF00, VDWord 0xFFFFFFFF]

exptSpec :: Spec
exptSpec = describe "Operators: EXPT (MT-OP-20)" $ do
  it "EXPT(4, 2) = 16 (the manual's example), flag FALSE" $
    expt mt (i 4) (u 2) `shouldBe` Right (i 16, Just False)
  it "EXPT(x, 0) = 1, also for 0, and 1.0 for REAL (even NaN)" $
    map (\b -> expt mt b (u 0)) [i 0, d (-5), u 0, r 0, r nan]
      `shouldBe` map (\v -> Right (v, Just False)) [i 1, d 1, u 1, r 1, r 1]
  it "INT EXPT(2, 15) = 32768 saturates to 32767 with the flag" $
    expt mt (i 2) (u 15) `shouldBe` Right (i 32767, Just True)
  it "INT EXPT(-2, 15) = -32768 exactly, flag FALSE" $
    expt mt (i (-2)) (u 15) `shouldBe` Right (i (-32768), Just False)
  it "INT EXPT(-2, 16) = 65536 saturates to 32767; EXPT(-2, 17) to -32768" $
    (expt mt (i (-2)) (u 16), expt mt (i (-2)) (u 17))
      `shouldBe` (Right (i 32767, Just True), Right (i (-32768), Just True))
  it "USINT EXPT(2, 7) = 128; EXPT(3, 5) = 243; EXPT(2, 8) saturates to 255" $
    map (\(b, e) -> expt mt (u b) (u e)) [(2, 7), (3, 5), (2, 8)]
      `shouldBe` [Right (u 128, Just False), Right (u 243, Just False), Right (u 255, Just True)]
  it "DINT EXPT(2, 31) saturates; EXPT(-2, 31) = -2147483648 exactly" $
    (expt mt (d 2) (u 31), expt mt (d (-2)) (u 31))
      `shouldBe` (Right (d 2147483647, Just True), Right (d (-2147483648), Just False))
  it "DINT EXPT(10, 255) saturates (no wrap-around through huge powers)" $
    expt mt (d 10) (u 255) `shouldBe` Right (d 2147483647, Just True)
  it "wrap: INT EXPT(2, 15) = -32768, EXPT(2, 16) = 0, both flagged" $
    (expt wrapP (i 2) (u 15), expt wrapP (i 2) (u 16))
      `shouldBe` (Right (i (-32768), Just True), Right (i 0, Just True))
  it "trap: INT EXPT(2, 15) traps" $
    expt trapP (i 2) (u 15) `shouldBe` Left trapOverflow
  it "promote-32: INT EXPT(2, 15) = 32768 fits 32 bits, stored as -32768, flag FALSE" $
    expt promote (i 2) (u 15) `shouldBe` Right (i (-32768), Just False)
  -- 2^40 leaves DINT: saturates to 16#7FFF_FFFF (flag), whose low word is
  -- 16#FFFF = -1 as INT.
  it "promote-32: INT EXPT(2, 40) saturates in 32 bits, then keeps the low word" $
    expt promote (i 2) (u 40) `shouldBe` Right (i (-1), Just True)
  it "REAL EXPT(2.0, 10) = 1024.0; EXPT(-2.0, 3) = -8.0" $
    (expt mt (r 2) (u 10), expt mt (r (-2)) (u 3))
      `shouldBe` (Right (r 1024, Just False), Right (r (-8), Just False))
  -- 3.3 is 13841203 * 2^-22. Its exact cube / 2^-18 = 9420668.5196...,
  -- rounded once: 9420669, pattern (149 - 18) * 2^23 + 9420669 = 16#420FBF7D.
  -- Two binary32 multiplications give 16#420FBF7C instead.
  it "REAL EXPT(3.3, 3) is the exact cube rounded once: 16#420FBF7D" $
    expt mt (bitsR 0x40533333) (u 3) `shouldBe` Right (bitsR 0x420FBF7D, Just False)
  it "REAL EXPT(10.0, 39) saturates with the flag; ieee gives +inf, flagged" $
    (expt mt (r 10) (u 39), expt ieee (r 10) (u 39))
      `shouldBe` (Right (r fltMax, Just True), Right (r posInf, Just True))
  it "REAL EXPT(-10.0, 39) saturates to -FLT_MAX" $
    expt mt (r (-10)) (u 39) `shouldBe` Right (r (negate fltMax), Just True)
  it "REAL EXPT(1.0e-30, 2) underflows to 0.0 (no flag); EXPT(-1.0e-30, 3) to -0.0" $
    (expt mt (r 1.0e-30) (u 2), expt mt (r (-1.0e-30)) (u 3))
      `shouldBe` (Right (r 0, Just False), Right (bitsR 0x80000000, Just False))
  it "REAL EXPT(-0.0, 3) = -0.0, EXPT(-0.0, 2) = 0.0" $
    (expt mt (r (-0.0)) (u 3), expt mt (r (-0.0)) (u 2))
      `shouldBe` (Right (bitsR 0x80000000, Just False), Right (r 0, Just False))
  it "REAL EXPT(-inf, 3) = -inf, not an overflow of EXPT" $
    expt mt (r negInf) (u 3) `shouldBe` Right (r negInf, Just False)
  it "an exponent that is not USINT is an internal error" $
    expt mt (i 2) (i 2) `shouldBe` Left errOperandTypes

-- * Laws

data IntCase = IntCase Value Value Integer Integer (Integer, Integer) Integer
  deriving (Show)

-- | Two operands of one integer type, their values, the type's range and 2^n.
genIntCase :: Gen IntCase
genIntCase =
  oneof
    [ mk (VUSInt . fromInteger) (0, 255) 256
    , mk (VInt . fromInteger) (-32768, 32767) 65536
    , mk (VDInt . fromInteger) (-2147483648, 2147483647) 4294967296
    ]
  where
    mk :: (Integer -> Value) -> (Integer, Integer) -> Integer -> Gen IntCase
    mk con rng@(lo, hi) m = do
      let inRange x = lo <= x && x <= hi
          edge = elements (filter inRange [lo, lo + 1, -1, 0, 1, 2, hi - 1, hi])
          val = oneof [edge, choose rng, choose (-300, 300) `suchThat` inRange]
      a <- val
      b <- val
      pure (IntCase (con a) (con b) a b rng m)

instance Arbitrary IntCase where
  arbitrary = genIntCase

exactOf :: ArithOp -> Integer -> Integer -> Integer
exactOf = \case
  OpAdd -> (+)
  OpSub -> (-)
  _ -> (*)

genAddSubMul :: Gen ArithOp
genAddSubMul = elements [OpAdd, OpSub, OpMul]

resultInteger :: Outcome -> Maybe (Integer, Maybe Bool)
resultInteger = \case
  Right (v, f) -> (,f) <$> valueToInteger v
  Left _ -> Nothing

finiteFloat :: Gen Float
finiteFloat =
  oneof
    [ (realFromBits <$> arbitrary) `suchThat` (\x -> not (isNaN x || isInfinite x))
    , fromIntegral <$> (choose (-100000, 100000) :: Gen Int)
    , elements [0, 1, -1, 0.1, 16777216, 3.0e38, -3.0e38, 1.0e-38, 1.0e-45]
    ]

-- | Finite binary32 values of large magnitude (biased exponent 190..254), so
-- that products and sums overflow often.
bigFloat :: Gen Float
bigFloat = do
  sign <- elements [0, 0x80000000]
  ex <- choose (190, 254)
  mant <- choose (0, 0x7FFFFF)
  pure (realFromBits (sign + ex * 0x800000 + mant))

laws :: Spec
laws = describe "Operators: laws" $ do
  it "saturate: result = exact clamped; flag TRUE iff exact out of range" $
    property $ forAll genAddSubMul $ \op (IntCase a b x y (lo, hi) _) ->
      let e = exactOf op x y
       in resultInteger (arith mt op a b) === Just (max lo (min hi e), Just (e < lo || e > hi))
  it "wrap: result = exact mod 2^n, in range; flag TRUE iff exact out of range" $
    property $ forAll genAddSubMul $ \op (IntCase a b x y (lo, hi) m) ->
      let e = exactOf op x y
       in case resultInteger (arith wrapP op a b) of
            Just (v, f) -> (v - e) `mod` m === 0 .&&. (lo <= v && v <= hi) .&&. f === Just (e < lo || e > hi)
            Nothing -> counterexample "no value" False
  it "trap: an error exactly when the exact result is out of range" $
    property $ forAll genAddSubMul $ \op (IntCase a b x y (lo, hi) _) ->
      let e = exactOf op x y
       in either (const True) (const False) (arith trapP op a b) === (e < lo || e > hi)
  it "division: x = y * (x / y) + x MOD y, |MOD| < |y|, sign rule of each mod-sign" $
    property $ \(IntCase a b x y (lo, hi) _) ->
      y /= 0 ==>
        conjoin
          [ case (resultInteger (arith p OpDiv a b), resultInteger (arith p OpMod a b)) of
              (Just (q, Nothing), Just (m, Nothing)) ->
                let exactQ = (x - m) `div` y
                 in (abs m < abs y)
                      .&&. signOk m
                      .&&. (if lo <= exactQ && exactQ <= hi then q === exactQ else q === hi)
              other -> counterexample (show other) False
          | (p, signOk) <-
              [ (mt, \m -> m == 0 || signum m == signum x)
              , (euclid, (>= 0))
              ]
          ]
  it "promote-32 on USINT and INT: never an overflow, the result keeps the low bits" $
    property $ forAll genAddSubMul $ \op (IntCase a b x y (lo, _) m) ->
      lo > -2147483648 ==>
        let e = exactOf op x y
         in case resultInteger (arith promote op a b) of
              Just (v, f) -> (v - e) `mod` m === 0 .&&. f === Just False
              Nothing -> counterexample "no value" False
  it "REAL + - *: the exact result rounded once to binary32 (when finite)" $
    property $ forAll ((,,) <$> genAddSubMul <*> finiteFloat <*> finiteFloat) $ \(op, x, y) ->
      let exact = exactOf' op (toRational x) (toRational y)
          rounded = roundToReal exact
       in not (isInfinite rounded) ==>
            arith mt op (VReal x) (VReal y) === Right (VReal rounded, Just False)
            .||. (exact == 0) -- the sign of an exact zero follows IEEE rules, not the rational
  it "REAL /: the exact quotient rounded once to binary32 (finite, nonzero divisor)" $
    property $ forAll ((,) <$> finiteFloat <*> finiteFloat) $ \(x, y) ->
      let rounded = roundToReal (toRational x / toRational y)
       in (y /= 0 && x /= 0 && not (isInfinite rounded)) ==>
            arith mt OpDiv (VReal x) (VReal y) === Right (VReal rounded, Nothing)
  it "REAL overflow: FLT_MAX of the sign and the flag under saturate, infinity under ieee" $
    checkCoverage $ forAll ((,,) <$> genAddSubMul <*> bigFloat <*> bigFloat) $ \(op, x, y) ->
      let rounded = roundToReal (exactOf' op (toRational x) (toRational y))
       in cover 10 (isInfinite rounded) "overflow" $ cover 10 (not (isInfinite rounded)) "no overflow" $
          if isInfinite rounded
            then
              arith mt op (VReal x) (VReal y) === Right (VReal (signum rounded * realFromBits 0x7F7FFFFF), Just True)
                .&&. arith ieee op (VReal x) (VReal y) === Right (VReal rounded, Just True)
            else
              arith mt op (VReal x) (VReal y) === Right (VReal rounded, Just False)
                .&&. arith ieee op (VReal x) (VReal y) === Right (VReal rounded, Just False)
  it "REAL: NaN operands propagate without a flag" $
    property $ forAll ((,) <$> genAddSubMul <*> finiteFloat) $ \(op, x) ->
      case arith mt op (VReal nan) (VReal x) of
        Right (VReal z, Just False) -> isNaN z
        _ -> False
  where
    exactOf' :: ArithOp -> Rational -> Rational -> Rational
    exactOf' = \case
      OpAdd -> (+)
      OpSub -> (-)
      _ -> (*)
