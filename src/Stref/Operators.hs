-- | Operators (catalogue §5, Tables 4-10 to 4-13) and EXPT (MT-OP-20): the
-- meaning of each operator on values, under the policies. STUB: owned by the
-- numeric work.
--
-- Operands already have their common type (the checker inserted the
-- conversions). A result is either a runtime error code (the interpreter
-- adds the line) or a value with the effect on INTERNAL_OVERFLOW: @Just b@
-- sets the flag to @b@ (+, -, *, unary -, EXPT; MT-OP-7), 'Nothing' leaves it.
module Stref.Operators
  ( Outcome
  , arith
  , negateValue
  , notValue
  , compareValues
  , logic
  , expt
  ) where

import Stref.Checked (ArithOp (..), CmpOp (..), LogicOp (..))
import Stref.Diagnostics (ErrorCode)
import Stref.Policy (Policies)
import Stref.Values

type Outcome = Either ErrorCode (Value, Maybe Bool)

arith :: Policies -> ArithOp -> Value -> Value -> Outcome
arith _ _ a _ = Right (a, Nothing)

negateValue :: Policies -> Value -> Outcome
negateValue _ a = Right (a, Nothing)

notValue :: Value -> Value
notValue = id

compareValues :: CmpOp -> Value -> Value -> Bool
compareValues _ _ _ = False

logic :: LogicOp -> Value -> Value -> Value
logic _ a _ = a

expt :: Policies -> Value -> Value -> Outcome
expt _ a _ = Right (a, Nothing)
