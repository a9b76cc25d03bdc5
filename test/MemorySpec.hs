-- | The operand memory with a module's cells held apart ('takeCells',
-- 'putCells'): it must behave as the one map it stands for.
module MemorySpec (spec) where

import qualified Data.Set as S
import Data.Word (Word32)
import Stref.Operands
import Stref.Types (BasicType (..))
import Stref.Values (Value (..))
import Test.Hspec
import Test.QuickCheck

cells :: [Cell]
cells = [CellSimple KM a | a <- [200 .. 205]] ++ [CellTable TM 10 p | p <- [0 .. 3]] ++ [CellSimple KI 20, CellSimple KE 1]

-- | %M0000..%M1999 and a table of 1000 positions.
manyCells :: [Cell]
manyCells = [CellSimple KM a | a <- [0 .. 1999]] ++ [CellTable TI 5 p | p <- [0 .. 999]]

writes :: Gen [(Cell, Word32)]
writes = listOf ((,) <$> elements cells <*> arbitrary)

apply :: [(Cell, Word32)] -> Memory -> Memory
apply ws mem = foldl (\m (c, w) -> writeCell c w m) mem ws

-- | The memory with the first @n@ cells held apart in a table.
held :: Int -> Memory -> Memory
held n mem =
  let table = cellSlots (take n cells)
      (rest, vals) = takeCells table mem
   in putCells table vals rest

spec :: Spec
spec = describe "Memory with cells held apart" $ do
  it "reads, writes, compares and shows as the memory it was taken from" $
    forAll ((,,) <$> writes <*> writes <*> choose (0, length cells)) $ \(before, after, n) ->
      let plain = apply after (apply before emptyMemory)
          apart = apply after (held n (apply before emptyMemory))
       in conjoin
            [ apart === plain
            , show apart === show plain
            , map (readCell apart) cells === map (readCell plain) cells
            , map (lookupCell apart) cells === map (lookupCell plain) cells
            ]
  it "finds every cell of a table at a slot holding it, and no other cell" $
    -- up to 3000 cells, with repetitions: a table far larger than a module's
    forAll (listOf (elements manyCells)) $ \given ->
      let table = cellSlots given
          slot c = lookupSlot table (cellKey c)
       in conjoin
            [ conjoin [counterexample (show c) (slot c >= 0) | c <- given]
            , length (filter (>= 0) (map slot manyCells)) === length (S.fromList given)
            , S.size (S.fromList (filter (>= 0) (map slot given))) === S.size (S.fromList given)
            ]
  it "distinguishes a cell never written from one written with 0, as the map does" $ do
    let c = CellSimple KM 200
        apart = held 3 emptyMemory
    lookupCell apart c `shouldBe` Nothing
    lookupCell (writeCell c 0 apart) c `shouldBe` Just 0
    (writeCell c 0 apart == apart) `shouldBe` False
  it "writes a bit of a held %M cell into its cell (MT-MAP-13)" $ do
    -- %M0202 = 16#00F0, then %M0202.3 := TRUE: 16#00F0 + 2^3 = 16#00F8 = 248
    let apart = held (length cells) (writeCell (CellSimple KM 202) 0x00F0 emptyMemory)
        mem = writeOperand (OpBit KM 202 3) (VBool True) apart
    readCell mem (CellSimple KM 202) `shouldBe` 248
    readOperand mem (OpSimple KM 202) INT `shouldBe` VInt 248
  it "masks a pattern to the held cell's width" $ do
    -- %M is 16 bits: 16#12345 keeps 16#2345 = 9029
    let apart = held (length cells) emptyMemory
    readCell (writeCell (CellSimple KM 201) 0x12345 apart) (CellSimple KM 201) `shouldBe` 9029
