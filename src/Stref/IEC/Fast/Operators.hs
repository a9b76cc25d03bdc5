{-# OPTIONS_GHC -O2 #-}
{-# LANGUAGE MagicHash #-}

-- | The operators and stores of "Stref.IEC.Fast" for integers of at most
-- 32 bits, with exactly the results of the readable ones ('binary' of
-- "Stref.IEC.Operators", 'fitWhy' of "Stref.IEC.Eval"), which stay the
-- definition: test/IEC/FastOperatorsSpec.hs checks the equality on random
-- values under every policy alternative.
--
-- Each function looks at the policies, the operator and the operands'
-- types once, when the program is translated, and returns the rest as a
-- closure in a strict constructor (which keeps GHC from moving that
-- analysis back into the closure). The closure computes on 'Int' only
-- where the outcome needs no policy: an exact result of + - * DIV MOD that
-- lies in the type's range is the result under every overflow policy
-- (TC-OP-20), a comparison is its truth, a bitwise operator its bits.
-- Anything else, and any operand of another form, goes to the readable
-- function.
module Stref.IEC.Fast.Operators
  ( Binary (..)
  , binaryOn
  , IntCase (..)
  , intCase
  , Store (..)
  , storeOn
  , storing
  , Convert (..)
  , convertOn
  , true
  , false
  , boolValue
  ) where

import Data.Bits (xor, (.&.), (.|.))
import GHC.Exts (Int (I#))
import GHC.Num (Integer (IS))
import Stref.IEC.Conversions (convert)
import Stref.IEC.Eval (fitWhy)
import Stref.IEC.Operators (binary, rangeUnder, strip)
import Stref.IEC.Syntax (BinOp (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

-- | A binary operator on two values.
data Binary = Binary !(Value -> Value -> Either Fault Value)

-- | A store into a target of a declared type: the value it keeps (or any
-- value as it is).
data Store = Store !(Value -> Either Fault Value) | KeepsAll

-- | 'binary' for operands of these types.
binaryOn :: Policies -> BinOp -> Type -> Type -> Binary
binaryOn p op ta tb = case (strip ta, strip tb) of
  (TElem e, TElem e') | e == e', isInt e, intBits e <= 32 -> small e
  _ -> Binary (binary p op)
  where
    small e =
      let (lo, hi) = rangeUnder p e
          !lo' = fromInteger lo :: Int
          !hi' = fromInteger hi :: Int
          -- both operands of the type, each a small Integer; else the
          -- readable operator
          on f = Binary $ \a b -> case (a, b) of
            (VInt ea (IS x), VInt eb (IS y)) | ea == e, eb == e -> f (I# x) (I# y) a b
            _ -> binary p op a b
          {-# INLINE on #-}
          exact g = on $ \x y a b ->
            let n = g x y
             in if lo' <= n && n <= hi' then Right (VInt e (toInteger n)) else binary p op a b
          {-# INLINE exact #-}
          -- a zero divisor is the policies'
          dividing g = on $ \x y a b ->
            if y == 0
              then binary p op a b
              else
                let n = g x y
                 in if lo' <= n && n <= hi' then Right (VInt e (toInteger n)) else binary p op a b
          {-# INLINE dividing #-}
          compared g = on (\x y _ _ -> Right (boolValue (g x y)))
          bitwise g = on (\x y _ _ -> Right (VInt e (toInteger (g x y))))
       in case intCase p op of
            Exact g -> exact g
            Dividing g -> dividing g
            Compared g -> compared g
            Bitwise g -> bitwise g
            NoIntCase -> Binary (binary p op)

-- | How an operator on two integers of at most 32 bits computes on 'Int'
-- where no policy applies ('binaryOn', and the closures on Int of
-- "Stref.IEC.Fast"): the exact result where it lies in the type's range
-- (TC-OP-20), the same with a non-zero divisor (TC-OP-21, TC-OP-23:
-- truncation toward zero, the dividend's sign), a comparison, the bits
-- (TC-OP-39: two's complement, as Integer's); or none.
data IntCase
  = Exact (Int -> Int -> Int)
  | Dividing (Int -> Int -> Int)
  | Compared (Int -> Int -> Bool)
  | Bitwise (Int -> Int -> Int)
  | NoIntCase

intCase :: Policies -> BinOp -> IntCase
intCase p = \case
  BAdd -> Exact (+)
  BSub -> Exact (-)
  BMul -> Exact (*)
  BDiv | pModSign p == ModSignDividend -> Dividing quot
  BMod | pModSign p == ModSignDividend -> Dividing rem
  BLt -> Compared (<)
  BGt -> Compared (>)
  BLe -> Compared (<=)
  BGe -> Compared (>=)
  BEq -> Compared (==)
  BNe -> Compared (/=)
  BAnd -> Bitwise (.&.)
  BOr -> Bitwise (.|.)
  BXor -> Bitwise xor
  _ -> NoIntCase
{-# INLINE intCase #-}

-- | 'fitWhy's value for a target of this type.
storeOn :: Policies -> Type -> Store
storeOn pol t = case t of
  TElem e
    | isInt e, intBits e <= 32 ->
        let (lo, hi) = intRange e
            !lo' = fromInteger lo :: Int
            !hi' = fromInteger hi :: Int
         in Store $ \case
              v@(VInt _ (IS n)) | lo' <= I# n && I# n <= hi' -> Right v
              v -> reference v
    | isInt e -> Store reference
    -- the other elementary types store any value as it is
    | otherwise -> KeepsAll
  TString {} -> Store reference
  TSubrange {} -> Store reference
  TArray {} -> Store reference
  TStruct {} -> Store reference
  _ -> KeepsAll
  where
    reference = fst . fitWhy pol t

-- | The outcome of a store.
storing :: Store -> Value -> Either Fault Value
storing = \case
  Store f -> f
  KeepsAll -> Right

-- | A conversion from a type to another.
data Convert = Convert !(Value -> Either Fault Value)

-- | 'convert' from this type to that: an integer to an integer type whose
-- range holds it is the same number (no policy applies).
convertOn :: Policies -> Type -> Type -> Convert
convertOn pol from to = case (from, to) of
  (TElem x, TElem y)
    | isInt x, isInt y, intBits y <= 32 ->
        let (lo, hi) = rangeUnder pol y
            !lo' = fromInteger lo :: Int
            !hi' = fromInteger hi :: Int
         in Convert $ \case
              VInt _ n@(IS i) | lo' <= I# i && I# i <= hi' -> Right (VInt y n)
              v -> reference v
  _ -> Convert reference
  where
    reference = convert pol from to

-- | The two values of BOOL, built once (a comparison's result is one of
-- them, not a new value).
true, false :: Value
true = VBool True
false = VBool False
{-# NOINLINE true #-}
{-# NOINLINE false #-}

boolValue :: Bool -> Value
boolValue b = if b then true else false
{-# INLINE boolValue #-}
