-- | Values known before the program runs: initialisers (MT-VAR-4, MT-ARR-6),
-- array bounds (MT-ARR-1) and CASE labels (MT-STMT-8). A constant is built
-- from literals, CONSTANT names (MT-VAR-7), operators and conversions.
module Stref.Check.Const
  ( constValueAt
  , constInteger
  ) where

import Control.Monad.Reader (asks)
import Data.Maybe (isJust)
import qualified Data.Text as T
import Stref.Check.Expr
import Stref.Check.Monad
import Stref.Checked
import Stref.Conversions (convert, lookupConversionFunction)
import Stref.Operators
import Stref.Policy (Policies)
import Stref.Syntax
import Stref.Types
import Stref.Values

-- | Is the expression made only of constant parts? Reports why not.
constShape :: Expr Pos -> Check Bool
constShape = \case
  ELit {} -> pure True
  EUnary _ _ e -> constShape e
  EBinary _ _ a b -> (&&) <$> constShape a <*> constShape b
  ECall _ name [a]
    | isJust (lookupConversionFunction (identText name)) -> constShape a
  ECall pos name args
    | T.toUpper (identText name) == "EXPT", length args == 2 -> and <$> mapM constShape args
    | otherwise -> notConstant pos ("the call of " <> identText name <> " is not a constant")
  EIndex pos name _ -> notConstant pos ("the array element " <> identText name <> "[...] is not a constant")
  EVar pos name ->
    resolveName name >>= \case
      RVar vs
        | vsRole vs == RoleConstant -> do
            known <- lookupConstant (vsVar vs)
            case known of
              Just _ -> pure True
              Nothing -> False <$ report "not-a-constant" pos (identText name <> " is a CONSTANT mapped to an operand without an initial value; its value is not known before the program runs")
        | otherwise -> False <$ report "not-a-constant" pos (identText name <> " is not a CONSTANT; only literals and CONSTANT names are allowed here") -- MT-VERR-24
      RUndeclared -> False <$ report "undeclared-variable" pos ("the variable " <> identText name <> " is not declared")
      _ -> False <$ report "not-a-constant" pos (identText name <> " is not a constant")
  where
    notConstant pos msg = False <$ report "not-a-constant" pos msg

-- | The value of a constant expression at a type (with the implicit
-- conversions and literal rules of any other context).
constValueAt :: BasicType -> Expr Pos -> Check (Maybe Value)
constValueAt t e = do
  ok <- constShape e
  if not ok
    then pure Nothing
    else
      checkAt t e >>= \case
        Nothing -> pure Nothing
        Just c -> do
          p <- asks envPolicies
          consts <- getConstants
          case foldConst p consts c of
            Right v -> pure (Just v)
            Left why -> Nothing <$ report "invalid-constant-expression" (exprAnn e) why

-- | Evaluate a checked constant expression with the operators' meaning.
foldConst :: Policies -> [(Var, Value)] -> CExpr -> Either T.Text Value
foldConst p consts = go
  where
    go = \case
      CLit v -> Right v
      CRead v -> maybe (Left ("the value of " <> varName v <> " is not known before the program runs")) Right (lookup v consts)
      CConv s t e -> convertConst p s t <$> go e
      CNeg _ _ e -> go e >>= outcome . negateValue p
      CNot _ e -> notValue <$> go e
      CArith _ op _ a b -> do
        x <- go a
        y <- go b
        outcome (arith p op x y)
      CCompare op _ a b -> VBool <$> (compareValues op <$> go a <*> go b)
      CLogic op _ a b -> logic op <$> go a <*> go b
      CExpt _ _ a b -> do
        x <- go a
        y <- go b
        outcome (expt p x y)
      CReadIndex {} -> Left "an array element is not a constant"
      CCall {} -> Left "a function call is not a constant"
    outcome = either (\code -> Left ("evaluating this constant raises runtime error " <> tshow code)) (Right . fst)

-- | Conversions of constants: the value-preserving ones exactly, the others
-- with the run-time meaning of Table 4-6.
convertConst :: Policies -> BasicType -> BasicType -> Value -> Value
convertConst p s t v = case valueToInteger v of
  Just n
    | s /= BOOL, t == REAL -> VReal (fromInteger n)
    | s /= BOOL, Just (lo, hi) <- intRange t, lo <= n, n <= hi, sameFamily -> integerToValue t n
  _ -> convert p s t v
  where
    sameFamily = isBitString s == isBitString t

-- | An integer constant: an array bound or a CASE label.
constInteger :: Expr Pos -> Check (Maybe Integer)
constInteger e = do
  ok <- constShape e
  if not ok
    then pure Nothing
    else
      checkNoContext e >>= \case
        Nothing -> pure Nothing
        Just c
          | cexprType c == REAL || cexprType c == BOOL -> do
              report "integer-expression-expected" (exprAnn e) ("an integer constant is expected here, not a " <> typeName (cexprType c))
              pure Nothing
          | otherwise -> do
              p <- asks envPolicies
              consts <- getConstants
              case foldConst p consts c of
                Right v -> pure (valueToInteger v)
                Left why -> Nothing <$ report "invalid-constant-expression" (exprAnn e) why
