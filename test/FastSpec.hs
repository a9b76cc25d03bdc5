-- | The interpreter's fast paths (Stref.Eval.Fast) against the reference
-- operators and conversions: the same outcome, value bits and flag included,
-- for random operands of every type under random policies.
module FastSpec (spec) where

import Data.Int (Int16, Int32)
import Data.Word (Word16, Word32, Word8)
import Stref.Checked (ArithOp (..), CmpOp (..))
import Stref.Conversions (convert)
import Stref.Eval.Fast
import Stref.Operands (Cell (..))
import qualified Stref.Operators as O
import Stref.Policy
import Stref.Types
import Stref.Values
import Test.Hspec
import Test.QuickCheck

every :: (Enum a, Bounded a) => Gen a
every = elements [minBound .. maxBound]

genPolicies :: Gen Policies
genPolicies = do
  o <- every
  w <- every
  dz <- every
  rdz <- every
  ro <- every
  mz <- every
  ms <- every
  rti <- every
  ni <- every
  pure
    mastertoolXE
      { pOverflow = o
      , pArithWidth = w
      , pDivZero = dz
      , pRealDivZero = rdz
      , pRealOverflow = ro
      , pModZero = mz
      , pModSign = ms
      , pRealToInt = rti
      , pNarrowInt = ni
      }

-- | Small numbers, the limits and their neighbours, and arbitrary bit patterns.
genBits :: forall a. (Bounded a, Integral a) => (a -> Value) -> Gen Value
genBits mk =
  mk
    <$> frequency
      [ (3, fromInteger <$> choose (-300, 300))
      , (2, elements [minBound, minBound + 1, maxBound - 1, maxBound, 0, 1, -1])
      , (3, fromInteger <$> choose (toInteger (minBound :: a), toInteger (maxBound :: a)))
      ]

genReal :: Gen Value
genReal =
  VReal
    <$> frequency
      [ (3, realFromBits <$> arbitrary)
      , (3, fromIntegral <$> (choose (-100000, 100000) :: Gen Int))
      , (2, elements [0, -0.0, 1, -1, 0.5, 3.0e38, -3.0e38, 1 / 0, -1 / 0, 0 / 0, 16777217, 2147483648, -2147483904])
      , -- halves (ties of round-even, MT-CONV-9) and the edges of INT and DINT
        (2, (/ 2) . fromIntegral <$> (choose (-100001, 100001) :: Gen Int))
      , (1, elements [2.5, -2.5, 3.5, -0.5, 32767.5, -32768.5, 32768, -32769, 2147483520, -2147483648, 2147483904])
      ]

genOfType :: BasicType -> Gen Value
genOfType = \case
  BOOL -> VBool <$> arbitrary
  BYTE -> genBits (VByte :: Word8 -> Value)
  WORD -> genBits (VWord :: Word16 -> Value)
  DWORD -> genBits (VDWord :: Word32 -> Value)
  USINT -> genBits (VUSInt :: Word8 -> Value)
  INT -> genBits (VInt :: Int16 -> Value)
  DINT -> genBits (VDInt :: Int32 -> Value)
  REAL -> genReal

-- | Cells with few distinct kinds and addresses, so that ties occur.
genCell :: Gen Cell
genCell =
  oneof
    [ CellSimple <$> every <*> choose (0, 3)
    , CellTable <$> every <*> choose (0, 3) <*> choose (0, 3)
    ]

cellKey :: Cell -> (Int, Int, Int, Int)
cellKey = \case
  CellSimple k a -> (0, fromEnum k, a, 0)
  CellTable k a p -> (1, fromEnum k, a, p)

-- | Same type, or (rarely) two different types, which the reference rejects.
genPair :: Gen (Value, Value)
genPair = do
  t <- every
  u <- frequency [(9, pure t), (1, every)]
  (,) <$> genOfType t <*> genOfType u

spec :: Spec
spec = describe "Fast paths of the interpreter" $ do
  it "arithFast gives the outcome of Operators.arith" $
    property $ withMaxSuccess 3000 $ forAll ((,,) <$> genPolicies <*> every <*> genPair) $ \(p, op :: ArithOp, (a, b)) ->
      let Binary f = arithFast p op (valueType a) in resultOutcome (f a b) === O.arith p op a b
  it "compareFast gives the result of Operators.compareValues" $
    property $ withMaxSuccess 3000 $ forAll ((,) <$> every <*> genPair) $ \(op :: CmpOp, (a, b)) ->
      let Binary f = compareFast op in f a b === O.compareValues op a b
  it "convertFast gives the result of Conversions.convert" $
    property $ withMaxSuccess 3000 $ forAll ((,,) <$> genPolicies <*> every <*> every) $ \(p, from, to) ->
      let Unary f = convertFast p from to in forAll (genOfType from) $ \v -> f v === convert p from to v
  it "valueToInt agrees with valueToInteger" $
    property $ forAll (every >>= genOfType) $ \v ->
      fmap toInteger (valueToInt v) === valueToInteger v
  it "orders operand cells as a derived instance would (simple first, then kind, address, position)" $
    property $ forAll ((,) <$> genCell <*> genCell) $ \(a, b) ->
      compare a b === compare (cellKey a) (cellKey b)
  it "saturates INT addition at 32767 and raises the flag (MT-OP-6, MT-OP-7)" $
    -- 32000 + 1000 = 33000 > 32767
    let Binary add = arithFast mastertoolXE OpAdd INT in add (VInt 32000) (VInt 1000) `shouldBe` Flagged (VInt 32767) True
