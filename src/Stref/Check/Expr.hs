{-# LANGUAGE MultiWayIf #-}

-- | Typing of expressions (catalogue §§ 3-5): literals take the type of
-- their context (Table 4-15), implicit conversions become 'CConv' nodes,
-- operators are checked against Tables 4-10..4-13.
module Stref.Check.Expr
  ( Typed (..)
  , Flex (..)
  , checkExpr
  , checkAt
  , checkNoContext
  , coerce
  , checkIndexExpr
  , checkUserCall
  , typedType
  , intLitAt
  ) where

import Control.Monad (zipWithM)
import Control.Monad.Reader (asks)
import Data.Either (isRight)
import qualified Data.Map.Lazy as M
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Check.Monad
import Stref.Checked
import Stref.Conversions
import Stref.Numeric (fitsIn, isRealInfinite, realLiteral)
import Stref.Policy
import Stref.Syntax
import Stref.Types
import Stref.Values
import Stref.Verification

-- | A typed expression, or one made only of literals whose type is still
-- open: it takes the type of its context (MT-CONST-1, decision A11).
data Typed
  = Fixed CExpr
  | Open Flex

data Flex = Flex
  { flexDefault :: BasicType
  -- ^ the type when the context gives none (A11: INT, DINT or DWORD)
  , flexAt :: BasicType -> Either [VerificationError] CExpr
  }

typedType :: Typed -> BasicType
typedType = \case
  Fixed e -> cexprType e
  Open f -> flexDefault f

tname :: BasicType -> Text
tname = typeName

-- | An integer literal at a type (Table 4-15, MT-CONST-1..6, MT-LEX-16).
-- In a REAL context it must fit an integer type that converts to REAL
-- implicitly: INT under MasterTool (MT-CONST-4, A10), so -32768..32767.
intLitAt :: ImplicitConversions -> Pos -> Integer -> BasicType -> Either [VerificationError] CExpr
intLitAt policy pos v t = case t of
  REAL
    | null viaTypes -> Left [outOfLimits]
    | otherwise -> Right (CLit (VReal (realLiteral (fromInteger v)))) -- exact for these ranges
  BOOL
    | v == 0 || v == 1 -> Right (CLit (VBool (v == 1))) -- MT-LEX-16
    | otherwise -> Left [outOfLimits]
  _
    | fitsIn t v -> Right (CLit (integerToValue t v))
    | otherwise -> Left [outOfLimits] -- MT-CONST-5, A12
  where
    viaTypes = [s | s <- [USINT, BYTE, INT, WORD, DINT, DWORD], implicitConversion policy s REAL, fitsIn s v]
    outOfLimits =
      verificationError "value-out-of-limits" pos $
        "the value " <> tshow v <> " is out of the limits of " <> tname t <> rangeText
    rangeText = case intRange t of
      Just (lo, hi) -> " (" <> tshow lo <> ".." <> tshow hi <> ")"
      Nothing
        | t == BOOL -> " (only 0 and 1 stand for FALSE and TRUE)"
        | otherwise ->
            " for an integer constant: only values of a type that converts to REAL implicitly are accepted ("
              <> T.intercalate ", " [typeName s <> " " <> maybe "" (\(lo, hi) -> tshow lo <> ".." <> tshow hi) (intRange s) | s <- [USINT, BYTE, INT, WORD, DINT, DWORD], implicitConversion policy s REAL]
              <> "); write it as a real constant, e.g. "
              <> tshow v
              <> ".0"

-- | A real literal is allowed only where a REAL is expected (MT-CONST-3).
realLitAt :: Pos -> Rational -> BasicType -> Either [VerificationError] CExpr
realLitAt pos q t
  | t /= REAL =
      Left [verificationError "impossible-conversion" pos ("impossible to convert the REAL constant to " <> tname t <> "; a real constant can only be used with REAL operands")]
  | isRealInfinite r = Left [verificationError "value-out-of-limits" pos "the real constant is out of the limits of REAL (about 3.4E38)"]
  | otherwise = Right (CLit (VReal r))
  where
    r = realLiteral q

negateLiteral :: CExpr -> CExpr
negateLiteral = \case
  CLit (VReal r) -> CLit (VReal (negate r))
  e -> e

-- | A11: the smallest of INT, DINT, DWORD that holds the value.
intDefault :: Integer -> BasicType
intDefault v = case [t | t <- [INT, DINT, DWORD], fits t] of
  (t : _) -> t
  [] -> if v < 0 then DINT else DWORD
  where
    fits t = fitsIn t v

intLiteral :: ImplicitConversions -> Pos -> Integer -> Typed
intLiteral policy pos v = Open (Flex (intDefault v) (intLitAt policy pos v))

checkExpr :: Expr Pos -> Check (Maybe Typed)
checkExpr expr = do
  policy <- asks (pImplicitConversions . envPolicies)
  checkExprWith policy expr

checkExprWith :: ImplicitConversions -> Expr Pos -> Check (Maybe Typed)
checkExprWith policy = \case
  ELit pos lit -> pure . Just $ case lit of
    LInt v _ -> intLiteral policy pos v
    LReal q -> Open (Flex REAL (realLitAt pos q))
    LBool b -> Fixed (CLit (VBool b))
  EVar pos name -> fmap Fixed <$> readVariable pos name
  EIndex pos name idx -> fmap Fixed <$> readIndexed pos name idx
  ECall pos name args -> checkCall pos name args
  -- MT-LEX-19: a minus before an integer literal makes a negative literal
  EUnary pos Neg (ELit _ (LInt v _)) -> pure (Just (intLiteral policy pos (negate v)))
  -- the same for a real literal: no negation at run time (so INTERNAL_OVERFLOW
  -- is not touched, A5); the sign of -0.0 is kept
  EUnary pos Neg (ELit _ (LReal q)) -> pure (Just (Open (Flex REAL (fmap negateLiteral . realLitAt pos q))))
  EUnary pos op e -> checkExpr e >>= maybe (pure Nothing) (unary pos op)
  EBinary pos op a b -> do
    ta <- checkExpr a
    tb <- checkExpr b
    case (ta, tb) of
      (Just x, Just y) -> binary pos op x y
      _ -> pure Nothing

-- | An expression where the context expects the given type.
checkAt :: BasicType -> Expr Pos -> Check (Maybe CExpr)
checkAt t e = checkExpr e >>= maybe (pure Nothing) (coerce (exprAnn e) t)

-- | An expression without a context type: literals take their default.
checkNoContext :: Expr Pos -> Check (Maybe CExpr)
checkNoContext e = checkExpr e >>= \case
  Nothing -> pure Nothing
  Just (Fixed c) -> pure (Just c)
  Just (Open f) -> liftEither (flexAt f (flexDefault f))

liftEither :: Either [VerificationError] a -> Check (Maybe a)
liftEither = either (\es -> Nothing <$ reportAll es) (pure . Just)

-- | Bring a typed expression to the expected type: the same type, an
-- implicit conversion edge (MT-CONV-6, MT-CONV-11), or a literal that fits.
coerce :: Pos -> BasicType -> Typed -> Check (Maybe CExpr)
coerce pos t = \case
  Open f -> liftEither (flexAt f t)
  Fixed e -> do
    let s = cexprType e
    policy <- asks (pImplicitConversions . envPolicies)
    if
        | s == t -> pure (Just e)
        | implicitConversion policy s t -> pure (Just (CConv s t e))
        | otherwise -> do
            report "impossible-conversion" pos $ -- MT-CONV-12, MT-VERR-12
              "impossible to convert " <> tname s <> " to " <> tname t <> "; use the explicit conversion " <> explicitName s t <> "(...)"
            pure Nothing

-- | The conversion function to suggest: the row of Table 4-6, or ANY_TO_
-- where the row is missing (MT-CONV-7).
explicitName :: BasicType -> BasicType -> Text
explicitName s t = case conversionRow s t of
  Just _ -> conversionName s t
  Nothing -> "ANY_TO_" <> tname t

readVariable :: Pos -> Ident -> Check (Maybe CExpr)
readVariable pos name =
  resolveName name >>= \case
    RVar vs
      | not (canRead (vsRole vs)) -> do
          report "read-not-allowed" pos (identText name <> " is " <> roleWord (vsRole vs) <> " and cannot be read") -- MT-VERR-25
          pure Nothing
      | Array {} <- varType (vsVar vs) -> do
          report "whole-array-use" pos ("the array " <> identText name <> " can only be used element by element, e.g. " <> identText name <> "[i]") -- A22
          pure Nothing
      | otherwise -> pure (Just (CRead (vsVar vs)))
    RFunction {} -> notAVariable "a function; call it with its arguments"
    RProgram _ -> notAVariable "the program's name"
    RUndeclared -> do
      report "undeclared-variable" pos ("the variable " <> identText name <> " is not declared") -- MT-VERR-8
      pure Nothing
  where
    notAVariable what = do
      report "not-a-variable" pos (identText name <> " is " <> what <> ", not a variable") -- MT-VERR-23
      pure Nothing

readIndexed :: Pos -> Ident -> Expr Pos -> Check (Maybe CExpr)
readIndexed pos name idx = do
  target <- resolveArray pos name
  i <- checkIndexExpr idx
  case target of
    Just vs
      | not (canRead (vsRole vs)) -> do
          report "read-not-allowed" pos (identText name <> " is " <> roleWord (vsRole vs) <> " and cannot be read") -- MT-VERR-25
          pure Nothing
      | otherwise -> pure (CReadIndex (line pos) (vsVar vs) <$> i)
    Nothing -> pure Nothing

-- | The array a name denotes (MT-VERR-9, MT-VERR-22).
resolveArray :: Pos -> Ident -> Check (Maybe VarSym)
resolveArray pos name =
  resolveName name >>= \case
    RVar vs | Array {} <- varType (vsVar vs) -> pure (Just vs)
    RUndeclared -> do
      report "undeclared-array" pos ("the array " <> identText name <> " is not declared")
      pure Nothing
    _ -> do
      report "not-an-array" pos (identText name <> " is not an array and cannot be indexed")
      pure Nothing

-- | An index: USINT, INT or DINT (MT-ARR-2), converted to DINT.
checkIndexExpr :: Expr Pos -> Check (Maybe CExpr)
checkIndexExpr e =
  checkExpr e >>= \case
    Nothing -> pure Nothing
    Just (Open f)
      | isAnyInt (flexDefault f) || flexDefault f == DWORD -> liftEither (flexAt f DINT)
    Just (Fixed c)
      | cexprType c == DINT -> pure (Just c)
      | isAnyInt (cexprType c) -> pure (Just (CConv (cexprType c) DINT c))
    Just t -> do
      report "integer-expression-expected" (exprAnn e) ("an array index must be a USINT, INT or DINT expression, not " <> tname (typedType t))
      pure Nothing

-- | MT-OP-4, MT-OP-11, MT-OP-12, A15: may the operator act on operands of
-- this (common) type?
binOpAllowed :: BinOp -> BasicType -> Bool
binOpAllowed op t = case op of
  Mod -> isAnyInt t
  _ | op `elem` [Add, Sub, Mul, Div, Lt, Gt, Le, Ge] -> isAnyNum t
  _ | op `elem` [Eq, Ne] -> True
  _ -> isAnyBit t -- AND, OR, XOR (MT-OP-14)

isComparison :: BinOp -> Bool
isComparison op = op `elem` [Lt, Gt, Le, Ge, Eq, Ne]

invalidBinary :: Pos -> BinOp -> BasicType -> BasicType -> VerificationError
invalidBinary pos op s t =
  verificationError "invalid-binary-operation" pos $ -- MT-VERR-13
    "the operation " <> binOpSymbol op <> " is not possible between " <> tname s <> " and " <> tname t

-- | Build the node of a binary operation whose operands have type @t@.
buildBinary :: Pos -> BinOp -> BasicType -> CExpr -> CExpr -> Either [VerificationError] CExpr
buildBinary pos op t a b
  | not (binOpAllowed op t) = Left [invalidBinary pos op t t]
  | otherwise = Right $ case op of
      Add -> CArith l OpAdd t a b
      Sub -> CArith l OpSub t a b
      Mul -> CArith l OpMul t a b
      Div -> CArith l OpDiv t a b
      Mod -> CArith l OpMod t a b
      Lt -> CCompare OpLt t a b
      Gt -> CCompare OpGt t a b
      Le -> CCompare OpLe t a b
      Ge -> CCompare OpGe t a b
      Eq -> CCompare OpEq t a b
      Ne -> CCompare OpNe t a b
      And -> CLogic OpAnd t a b
      Or -> CLogic OpOr t a b
      Xor -> CLogic OpXor t a b
  where
    l = line pos

both :: Either [e] a -> Either [e] b -> Either [e] (a, b)
both (Right a) (Right b) = Right (a, b)
both (Left e1) (Left e2) = Left (e1 ++ e2)
both (Left e) _ = Left e
both _ (Left e) = Left e

-- | The order in which a literal-only expression tries its types (A11).
literalRank :: BasicType -> Int
literalRank = \case
  INT -> 0
  DINT -> 1
  DWORD -> 2
  REAL -> 3
  _ -> 0

binary :: Pos -> BinOp -> Typed -> Typed -> Check (Maybe Typed)
binary pos op x y = case (x, y) of
  (Fixed a, Fixed b) -> do
    policy <- asks (pImplicitConversions . envPolicies)
    let s = cexprType a
        t = cexprType b
        -- MT-OP-3, MT-CONV-11 (b): one operand converts to the other's type
        common
          | s == t = Just (t, a, b)
          | implicitConversion policy s t = Just (t, CConv s t a, b)
          | implicitConversion policy t s = Just (s, a, CConv t s b)
          | otherwise = Nothing
    case common of
      Nothing -> Nothing <$ reportAll [invalidBinary pos op s t]
      Just (c, a', b') -> fmap Fixed <$> liftEither (buildBinary pos op c a' b')
  (Fixed a, Open f) -> withFixed (cexprType a) (\lit -> buildBinary pos op (cexprType a) a lit) f
  (Open f, Fixed b) -> withFixed (cexprType b) (\lit -> buildBinary pos op (cexprType b) lit b) f
  (Open f, Open g) -> do
    let atFresh t = both (flexAt f t) (flexAt g t) >>= uncurry (buildBinary pos op t)
        -- one lazy result per type, shared: choosing the type below tries
        -- several, and each try would otherwise redo the whole left operand
        -- (quadratic on a long chain of literals such as 1 + 2 + ... + n)
        table = M.fromList [(t, atFresh t) | t <- [minBound .. maxBound]]
        at t = M.findWithDefault (atFresh t) t table
        joined = if literalRank (flexDefault f) >= literalRank (flexDefault g) then flexDefault f else flexDefault g
        candidates
          | joined == REAL = [REAL]
          | otherwise = [t | t <- [INT, DINT, DWORD], literalRank t >= literalRank joined]
        chosen = case [t | t <- candidates, isRight (at t)] of
          (t : _) -> t
          [] -> joined
    if isComparison op
      then fmap Fixed <$> liftEither (at chosen) -- the result is BOOL whatever the operand type
      else pure (Just (Open (Flex chosen at)))
  where
    -- the literal side takes the type of the other operand (MT-CONST-1)
    withFixed t build f
      | not (binOpAllowed op t) = Nothing <$ reportAll [invalidBinary pos op t t]
      | otherwise = fmap Fixed <$> liftEither (flexAt f t >>= build)

unary :: Pos -> UnOp -> Typed -> Check (Maybe Typed)
unary pos op = \case
  Fixed e -> fmap Fixed <$> liftEither (build (cexprType e) e)
  Open f -> pure (Just (Open (Flex (flexDefault f) (\t -> flexAt f t >>= build t))))
  where
    build t e
      | allowed t = Right (node t e)
      | otherwise =
          Left [verificationError "invalid-unary-operation" pos ("the operation " <> unOpSymbol op <> " is not possible with " <> tname t)] -- MT-VERR-14
    allowed t = case op of
      Neg -> t `elem` [INT, DINT, REAL] -- MT-OP-4, MT-OP-5
      Not -> isAnyBit t -- MT-OP-14
    node t e = case op of
      Neg -> CNeg (line pos) t e
      Not -> CNot t e

arityError :: Pos -> Text -> Int -> Int -> Check ()
arityError pos name expected given
  | given > expected = report "too-many-arguments" pos (name <> " takes " <> tshow expected <> " argument(s) but is called with " <> tshow given) -- MT-VERR-19
  | otherwise = report "too-few-arguments" pos (name <> " takes " <> tshow expected <> " argument(s) but is called with only " <> tshow given) -- MT-VERR-20

checkCall :: Pos -> Ident -> [Expr Pos] -> Check (Maybe Typed)
checkCall pos name args
  | T.toUpper (identText name) == "EXPT" = checkExpt pos args -- MT-OP-20
  | Just cf <- lookupConversionFunction (identText name) = checkConversion pos name cf args -- MT-CONV-2, MT-CONV-8
  | otherwise = fmap (\(i, sig, cargs) -> Fixed (CCall (line pos) i (fsResult sig) cargs)) <$> checkUserCall pos name args

-- | Check every argument even when the count is wrong, so that all errors
-- are seen.
checkArgsLoose :: [Expr Pos] -> Check ()
checkArgsLoose = mapM_ checkExpr

checkExpt :: Pos -> [Expr Pos] -> Check (Maybe Typed)
checkExpt pos = \case
  [base, ex] -> do
    tb <- checkExpr base
    te <- checkAt USINT ex -- the exponent is USINT; a literal exponent is typed USINT
    let allowed t = isAnyInt t || t == REAL
        build e t b
          | allowed t = Right (CExpt (line pos) t b e)
          | otherwise = Left [verificationError "invalid-binary-operation" pos ("EXPT is not possible with a base of type " <> tname t <> "; the base must be USINT, INT, DINT or REAL")]
    case (tb, te) of
      (Just (Fixed b), Just e) -> fmap Fixed <$> liftEither (build e (cexprType b) b)
      (Just (Open f), Just e) -> pure (Just (Open (Flex (flexDefault f) (\t -> flexAt f t >>= build e t))))
      _ -> pure Nothing
  args -> Nothing <$ (arityError pos "EXPT" 2 (length args) >> checkArgsLoose args)

checkConversion :: Pos -> Ident -> ConversionFunction -> [Expr Pos] -> Check (Maybe Typed)
checkConversion pos name cf = \case
  [arg] -> case cf of
    Explicit s t -> fmap (Fixed . CConv s t) <$> checkAt s arg
    AnyTo t ->
      checkExpr arg >>= \case
        Nothing -> pure Nothing
        Just typed -> do
          -- MT-CONV-8: the row for the argument's static type
          let s = typedType typed
          e <- coerce (exprAnn arg) s typed
          pure $ Fixed . anyTo s t <$> e
  args -> Nothing <$ (arityError pos (identText name) 1 (length args) >> checkArgsLoose args)
  where
    anyTo s t e
      | s == t = e
      | Just _ <- conversionRow s t = CConv s t e
      | otherwise = CConv DINT t (CConv REAL DINT e) -- MT-CONV-7, A8: REAL to BYTE/USINT/DWORD via DINT

-- | A call of a user function: its id, signature and converted arguments.
checkUserCall :: Pos -> Ident -> [Expr Pos] -> Check (Maybe (FunId, FunSig, [CExpr]))
checkUserCall pos name args = do
  pou <- asks envPou
  p <- asks envPolicies
  case pou of
    PouFunction self key _ | key == nameKey p name -> do
      report "recursive-call" pos ("the function " <> identText name <> " calls itself; recursion is not allowed") -- MT-POU-8, MT-VERR-17
      recordCall self pos
      Nothing <$ checkArgsLoose args
    _ ->
      resolveName name >>= \case
        RFunction i sig -> do
          recordCall i pos
          let n = length (fsParams sig)
          if length args /= n
            then Nothing <$ (arityError pos (identText name) n (length args) >> checkArgsLoose args)
            else do
              -- MT-CONV-11 (c): each argument converts to its parameter's type
              cargs <- zipWithM (\t a -> checkAt t a) (fsParams sig) args
              pure ((i,sig,) <$> sequence cargs)
        RUndeclared -> do
          report "undeclared-function" pos ("the function " <> identText name <> " is not declared; declare a function before the code that calls it") -- MT-VERR-10, MT-OP-21
          Nothing <$ checkArgsLoose args
        _ -> do
          report "not-a-function" pos (identText name <> " is not a function") -- MT-VERR-21
          Nothing <$ checkArgsLoose args
