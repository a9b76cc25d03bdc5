-- | QuickCheck generators of well-typed MasterTool XE modules (catalogue
-- §§ 2-9), for laws and differential testing.
--
-- Expressions are generated as typed trees ('TExpr') for a target type, so
-- that every program is accepted by the checker by construction; 'toExpr'
-- erases the types to the surface syntax. The discipline that keeps the
-- checker's choices unambiguous:
--
-- * binary operands have one type after at most one implicit widening along
--   the 7 edges of MT-CONV-6; never two widened operands, never two literals;
-- * an integer literal only sits next to an operand that fixes its type
--   (MT-CONST-1), inside the Table 4-15 range of that type (MT-CONST-2);
--   REAL literals only in REAL contexts (MT-CONST-3);
-- * operands of NOT, unary minus, conversions and EXPT have exactly their
--   syntactic type (no implicit widening under them).
--
-- Whole modules: mapped globals (Table 4-8) hold the inputs and receive the
-- results, so a run's outcome is the operand state; functions call only
-- earlier functions (MT-POU-8, MT-POU-11); loops are bounded (FOR with
-- literal bounds and an unwritten control variable, WHILE/REPEAT driven by a
-- counter); EXIT and RETURN only end a statement list (MT-STMT-22).
module Stref.Generate.Program
  ( -- * Values
    genValue
  , genFiniteReal
  , edgeValues
  , shrinkValue
    -- * Typed expressions
  , TExpr (..)
  , Lit (..)
  , texprType
  , toExpr
  , litValue
  , decimalOf
  , Scope (..)
  , emptyScope
  , genExpr
  , genExactExpr
  , genLiteral
  , wellFormed
  , shrinkTExpr
  , implicitEdges
  , widensTo
    -- * Statements and modules
  , GStmt (..)
  , LocalVar (..)
  , GFunction (..)
  , GProgram (..)
  , MappedVar (..)
  , standardMapped
  , GArray (..)
  , arrayOperands
  , GenModule (..)
  , GenConfig (..)
  , defaultGenConfig
  , genModule
  , shrinkGenModule
  , toModule
  , moduleUsesCalls
  , observedOperands
  , initialMemory
  , generateWithSeed
  ) where

import Control.Monad (replicateM)
import Data.List (nub, (\\))
import Data.Maybe (isJust)
import Data.Text (Text)
import qualified Data.Text as T
import Numeric (floatToDigits)
import Stref.Checked (ArithOp (..), CmpOp (..), LogicOp (..))
import Stref.Conversions (ConversionRow (..), conversionName, conversionTable)
import Stref.Operands
import Stref.Syntax
import Stref.Types
import Stref.Values
import Test.QuickCheck
import Test.QuickCheck.Gen (unGen)
import Test.QuickCheck.Random (mkQCGen)

------------------------------------------------------------------------------
-- Values

-- | Finite binary32 values with the edges: 0, -0.0, the limits, the smallest
-- normal and subnormal, 2^24 and its neighbours, huge and tiny values.
genFiniteReal :: Gen Float
genFiniteReal =
  frequency
    [ (3, elements realEdges)
    , (3, (\m e -> encodeFloat m e) <$> choose (-(2 ^ (24 :: Int)), 2 ^ (24 :: Int)) <*> choose (-149, 104))
    , (2, fromIntegral <$> (choose (-1000, 1000) :: Gen Int))
    , (2, (/ 4) . fromIntegral <$> (choose (-400, 400) :: Gen Int))
    ]
  where
    realEdges =
      [ 0, -0.0, 1, -1, 0.5, -0.5, 1.5, -2.5, 3.4028235e38, -3.4028235e38, 1.1754944e-38, 1.0e-45, -1.0e-45
      , 16777216, 16777215, 2147483648, -2147483648, 2147483520, 32767.5, -32768.9, 1.0e10, 1.0e-10, 3.0e38, 65535.7
      ]

-- | MT-TYPE-1 edges of each type: 0, 1, -1, the limits, 16#8000 and friends.
edgeValues :: BasicType -> [Value]
edgeValues t = case t of
  BOOL -> [VBool False, VBool True]
  REAL -> map VReal [0, -0.0, 1, -1, 3.4028235e38, -3.4028235e38, 1.0e-45, 16777217]
  _ -> [integerToValue t n | n <- nub (edges t)]
  where
    edges ty = case intRange ty of
      Just (lo, hi) -> [0, 1, -1, lo, hi, lo + 1, hi - 1, 128, 255, 256, 32768, 32767, -32768, 65535, hi `div` 2]
      Nothing -> [0, 1]

genValue :: BasicType -> Gen Value
genValue = \case
  BOOL -> VBool <$> arbitrary
  REAL -> VReal <$> genFiniteReal
  t -> frequency [(2, elements (edgeValues t)), (2, small t), (2, anyOf t)]
  where
    small t = integerToValue t <$> choose (-100, 100)
    anyOf t = case intRange t of
      Just (lo, hi) -> integerToValue t <$> choose (lo, hi)
      Nothing -> pure (defaultValue t)

-- | Shrink a value towards 0 of its type.
shrinkValue :: Value -> [Value]
shrinkValue v = case v of
  VBool b -> [VBool False | b]
  VReal r -> [VReal x | x <- [0, 1, fromIntegral (truncate r :: Integer)], realBits x /= realBits r, abs x < abs r || x == 0]
  _ -> case valueToInteger v of
    Just n -> [integerToValue (valueType v) m | m <- shrinkIntegral n, inRange m]
    Nothing -> []
  where
    inRange m = maybe True (\(lo, hi) -> m >= lo && m <= hi) (intRange (valueType v))

------------------------------------------------------------------------------
-- Typed expressions

-- | A literal as written: an integer with its base (a negative one is printed
-- as unary minus applied to its magnitude, and folded back by the checker,
-- MT-LEX-19), a REAL, TRUE/FALSE.
data Lit = LitInt Integer Int | LitReal Float | LitBool Bool
  deriving (Show)

instance Eq Lit where
  LitInt a _ == LitInt b _ = a == b
  LitReal a == LitReal b = realBits a == realBits b
  LitBool a == LitBool b = a == b
  _ == _ = False

-- | Typed expressions. The 'BasicType' of a node is its result type, except
-- for 'TArith', 'TCmp' and 'TLogic' where it is the operands' common type.
data TExpr
  = TLit BasicType Lit -- ^ a literal in a context of the given type
  | TVar BasicType Text
  | TFlag -- ^ INTERNAL_OVERFLOW (MT-OP-7)
  | TWiden BasicType BasicType TExpr -- ^ implicit conversion, from and to (MT-CONV-6); no syntax
  | TConv BasicType BasicType TExpr -- ^ @S_TO_T(e)@ (Table 4-6)
  | TNeg BasicType TExpr -- ^ MT-OP-4: INT, DINT, REAL
  | TNot BasicType TExpr -- ^ MT-OP-14
  | TArith ArithOp BasicType TExpr TExpr
  | TCmp CmpOp BasicType TExpr TExpr
  | TLogic LogicOp BasicType TExpr TExpr
  | TExpt BasicType TExpr TExpr -- ^ MT-OP-20: base type; exponent USINT
  | TCall BasicType Text [TExpr] -- ^ a user function: result type, name, arguments
  | TIndex BasicType Text TExpr -- ^ an array element: element type, array, index of an ANY_INT type (MT-ARR-2)
  deriving (Eq, Show)

texprType :: TExpr -> BasicType
texprType = \case
  TLit t _ -> t
  TVar t _ -> t
  TFlag -> BOOL
  TWiden _ t _ -> t
  TConv _ t _ -> t
  TNeg t _ -> t
  TNot t _ -> t
  TArith _ t _ _ -> t
  TCmp {} -> BOOL
  TLogic _ t _ _ -> t
  TExpt t _ _ -> t
  TCall t _ _ -> t
  TIndex t _ _ -> t

-- | The value of a literal in its context type (REAL: the binary32 nearest
-- to the decimal that 'toExpr' prints, which is the 'Float' itself).
litValue :: BasicType -> Lit -> Value
litValue t = \case
  LitInt n _ -> if t == REAL then VReal (fromInteger n) else integerToValue t n
  LitReal r -> VReal r
  LitBool b -> VBool b

-- | The shortest decimal that reads back as the given non-negative binary32.
decimalOf :: Float -> Rational
decimalOf f
  | f == 0 = 0
  | otherwise =
      let (ds, e) = floatToDigits 10 f
          mant = foldl (\acc d -> acc * 10 + toInteger d) 0 ds
       in fromInteger mant * 10 ^^ (e - length ds)

-- | Erase the types: the surface syntax the printer and the checker see.
toExpr :: TExpr -> Expr ()
toExpr = \case
  TLit _ l -> case l of
    LitInt n b
      | n < 0 -> EUnary () Neg (ELit () (LInt (negate n) 10))
      | otherwise -> ELit () (LInt n b)
    LitReal r
      | r < 0 || isNegativeZero r -> EUnary () Neg (ELit () (LReal (decimalOf (negate r))))
      | otherwise -> ELit () (LReal (decimalOf r))
    LitBool b -> ELit () (LBool b)
  TVar _ n -> EVar () (Ident n)
  TFlag -> EVar () (Ident "INTERNAL_OVERFLOW")
  TWiden _ _ e -> toExpr e
  TConv f t e -> ECall () (Ident (conversionName f t)) [toExpr e]
  TNeg _ e -> EUnary () Neg (toExpr e)
  TNot _ e -> EUnary () Not (toExpr e)
  TArith op _ a b -> EBinary () (arithOp op) (toExpr a) (toExpr b)
  TCmp op _ a b -> EBinary () (cmpOp op) (toExpr a) (toExpr b)
  TLogic op _ a b -> EBinary () (logicOp op) (toExpr a) (toExpr b)
  TExpt _ a b -> ECall () (Ident "EXPT") [toExpr a, toExpr b]
  TCall _ f args -> ECall () (Ident f) (map toExpr args)
  TIndex _ a i -> EIndex () (Ident a) (toExpr i)
  where
    arithOp = \case
      OpAdd -> Add
      OpSub -> Sub
      OpMul -> Mul
      OpDiv -> Div
      OpMod -> Mod
    cmpOp = \case
      OpLt -> Lt
      OpGt -> Gt
      OpLe -> Le
      OpGe -> Ge
      OpEq -> Eq
      OpNe -> Ne
    logicOp = \case
      OpAnd -> And
      OpOr -> Or
      OpXor -> Xor

-- | MT-CONV-6: the seven implicit edges (not transitively closed, A9).
implicitEdges :: [(BasicType, BasicType)]
implicitEdges = [(BYTE, WORD), (BYTE, DWORD), (WORD, DWORD), (USINT, INT), (USINT, DINT), (INT, DINT), (INT, REAL)]

-- | The types that widen implicitly to the given one.
widensTo :: BasicType -> [BasicType]
widensTo t = [f | (f, t') <- implicitEdges, t' == t]

-- | What an expression may use.
data Scope = Scope
  { scVars :: [(Text, BasicType)] -- ^ readable scalar variables
  , scFlag :: Bool -- ^ may read INTERNAL_OVERFLOW
  , scFunctions :: [(Text, BasicType, [BasicType])] -- ^ callable functions: name, result, parameters
  , scArrays :: [GArray] -- ^ readable arrays
  , scNegativeReals :: Bool -- ^ may write negative REAL literals such as @-1.5@ (MT-LEX-14)
  }
  deriving (Show)

emptyScope :: Scope
emptyScope = Scope [] False [] [] True

-- | Table 4-15 (MT-CONST-2, MT-CONST-4): the integer literals a type admits.
literalRange :: BasicType -> (Integer, Integer)
literalRange = \case
  REAL -> (-32768, 32767) -- MT-CONST-4: through INT
  BOOL -> (0, 1)
  t -> maybe (0, 0) id (intRange t)

-- | A literal of the type (for BOOL TRUE/FALSE; for REAL a REAL literal, or
-- now and then an integer one, A10).
genLiteral :: BasicType -> Gen Lit
genLiteral = \case
  BOOL -> LitBool <$> arbitrary
  REAL -> frequency [(5, LitReal <$> genFiniteReal), (1, (`LitInt` 10) <$> choose (-300, 300))]
  t -> do
    let (lo, hi) = literalRange t
    n <-
      frequency
        [ (3, elements (filter (\x -> x >= lo && x <= hi) [0, 1, 2, -1, lo, hi, hi - 1, lo + 1, 100, 128, 255, 32767, 32768, 65535, -32768]))
        , (3, choose (max lo (-50), min hi 50))
        , (2, choose (lo, hi))
        ]
    base <- if n < 0 then pure 10 else frequency [(6, pure 10), (2, pure 16), (1, pure 2), (1, pure 8)]
    pure (LitInt n base)

-- | A literal as the scope allows it; @-0.0@ is never written as a literal.
scopedLiteral :: Scope -> BasicType -> Gen Lit
scopedLiteral sc t = fix <$> genLiteral t
  where
    fix = \case
      LitReal r
        | r == 0 -> LitReal 0
        | r < 0 && not (scNegativeReals sc) -> LitReal (negate r)
      l -> l

-- | Is a literal definite, i.e. does it fix its own type? Integer literals
-- take the type of their context (MT-CONST-1); REAL and BOOL ones do not.
isIntLiteral :: TExpr -> Bool
isIntLiteral = \case
  TLit _ (LitInt _ _) -> True
  _ -> False

-- | Unary minus on a literal reads like a negative literal (MT-LEX-19), so
-- the generator never writes one.
isLiteral :: TExpr -> Bool
isLiteral = \case
  TLit {} -> True
  _ -> False

-- | A numeric literal: its type is open until the context fixes it (the
-- checker's reading of MT-CONST-1 and A11), so two of them never meet and
-- one never sits next to a widened operand (MT-CONST-3).
isOpenLit :: TExpr -> Bool
isOpenLit = \case
  TLit _ (LitInt _ _) -> True
  TLit _ (LitReal _) -> True
  _ -> False

isWidened :: TExpr -> Bool
isWidened = \case
  TWiden {} -> True
  _ -> False

-- | A well-typed expression of the given type. The result may be an integer
-- literal (typed by its context) or an implicitly widened expression.
genExpr :: Scope -> BasicType -> Gen TExpr
genExpr sc t = sized $ \n ->
  frequency $
    [(1, TLit t <$> scopedLiteral sc t)]
      ++ [(4, genExactSized sc t (min n 12))]
      ++ [(1, widened sc t (min n 12)) | not (null (widensTo t))]

-- | A well-typed expression whose syntactic type is exactly the given one
-- and which fixes its own type (not an integer literal, not widened).
genExactExpr :: Scope -> BasicType -> Gen TExpr
genExactExpr sc t = sized $ \n -> genExactSized sc t (min n 12)

widened :: Scope -> BasicType -> Int -> Gen TExpr
widened sc t n = do
  s <- elements (widensTo t)
  TWiden s t <$> genExactSized sc s n

genExactSized :: Scope -> BasicType -> Int -> Gen TExpr
genExactSized sc t n
  | n <= 0 = leaf
  | otherwise = frequency (((2, leaf) :) compound)
  where
    m = n `div` 2
    vars = [TVar t v | (v, t') <- scVars sc, t' == t]
    arrays = [a | a <- scArrays sc, gaType a == t]
    leaf =
      oneof $
        [elements vars | not (null vars)]
          ++ [pure TFlag | t == BOOL, scFlag sc]
          ++ [TLit t <$> scopedLiteral sc t | t `elem` [BOOL, REAL]]
          ++ [elements arrays >>= \a -> TIndex t (gaName a) <$> genIndex sc a | not (null arrays)]
          ++ [conversionOfLiteral]
    conversionOfLiteral = do
      row <- elements [r | r <- conversionTable, crTo r == t]
      TConv (crFrom row) t . TLit (crFrom row) <$> scopedLiteral sc (crFrom row)
    isArith = t `elem` [USINT, INT, DINT, REAL]
    isBits = t `elem` [BOOL, BYTE, WORD, DWORD]
    calls = [(f, ps) | (f, r, ps) <- scFunctions sc, r == t]
    compound =
      [(3, arithNode) | isArith]
        ++ [(3, cmpNode) | t == BOOL]
        ++ [(2, logicNode) | isBits]
        ++ [(1, TNot t <$> genExactSized sc t m) | isBits]
        ++ [(1, TNeg t <$> (genExactSized sc t m `suchThat` (not . isLiteral))) | t `elem` [INT, DINT, REAL], not (null vars) || m > 0]
        ++ [(2, convNode)]
        ++ [(1, exptNode) | isArith]
        ++ [(2, callNode) | not (null calls)]
    arithNode = do
      op <- elements ([OpAdd, OpSub, OpMul, OpDiv] ++ [OpMod | t /= REAL])
      uncurry (TArith op t) <$> operands sc t m
    cmpNode = do
      s <- elements allBasicTypes
      op <- elements (if isAnyNum s then [OpLt, OpGt, OpLe, OpGe, OpEq, OpNe] else [OpEq, OpNe])
      uncurry (TCmp op s) <$> operands sc s m
    logicNode = do
      op <- elements [OpAnd, OpOr, OpXor]
      uncurry (TLogic op t) <$> operands sc t m
    convNode = do
      row <- elements [r | r <- conversionTable, crTo r == t]
      let s = crFrom row
      arg <- frequency [(3, genExactSized sc s m), (1, TLit s <$> scopedLiteral sc s)]
      pure (TConv s t arg)
    exptNode = do
      base <- genExactSized sc t m `suchThat` (not . isLiteral)
      ex <-
        frequency
          [ (3, TLit USINT . (`LitInt` 10) <$> frequency [(4, choose (0, 5)), (2, choose (6, 40)), (1, pure 255)])
          , (1, genExactSized sc USINT (m `div` 2))
          ]
      pure (TExpt t base ex)
    callNode = do
      (f, ps) <- elements calls
      TCall t f <$> mapM (\p -> resize m (genExpr sc p)) ps

-- | Two operands of one common type: each exact, or an integer literal, or
-- widened; never two literals and never two widened operands.
operands :: Scope -> BasicType -> Int -> Gen (TExpr, TExpr)
operands sc s m = do
  let exact = genExactSized sc s m
      lit = TLit s <$> scopedLiteral sc s
      wide = widened sc s m
      -- MT-CONST-3: no REAL literal next to a widened INT
      exactNoLit = exact `suchThat` (not . isLiteral)
      ok (a, b) = not (isOpenLit a && isOpenLit b)
      canWiden = not (null (widensTo s))
      intLit = s /= BOOL
  (`suchThat` ok) . frequency $
    [(4, (,) <$> exact <*> exact)]
      ++ [(2, (,) <$> exact <*> lit) | intLit]
      ++ [(1, (,) <$> lit <*> exact) | intLit]
      ++ [(1, (,) <$> exactNoLit <*> wide) | canWiden]
      ++ [(1, (,) <$> wide <*> exactNoLit) | canWiden]

-- | The typing discipline above, as a predicate (used to keep shrinks well
-- typed). Scope is not checked: shrinking never adds a name.
wellFormed :: TExpr -> Bool
wellFormed = \case
  TLit t l -> litOk t l
  TVar _ _ -> True
  TFlag -> True
  TWiden s t e -> (s, t) `elem` implicitEdges && exact s e
  TConv s t e -> isJust (lookupRow s t) && (exact s e || (isIntLiteral e && texprType e == s)) && wellFormed e
  TNeg t e -> t `elem` [INT, DINT, REAL] && exact t e && not (isLiteral e)
  TNot t e -> t `elem` [BOOL, BYTE, WORD, DWORD] && exact t e
  TArith op t a b -> isAnyNum t && (op /= OpMod || t /= REAL) && pair t a b
  TCmp op s a b -> (isAnyNum s || op `elem` [OpEq, OpNe]) && pair s a b
  TLogic _ t a b -> t `elem` [BOOL, BYTE, WORD, DWORD] && pair t a b
  TExpt t b e -> isAnyNum t && exact t b && not (isLiteral b) && (exact USINT e || (isIntLiteral e && texprType e == USINT)) && wellFormed e
  TCall _ _ args -> all wellFormed args
  TIndex _ _ i -> texprType i `elem` [USINT, INT, DINT] && wellFormed i
  where
    lookupRow s t = case [r | r <- conversionTable, crFrom r == s, crTo r == t] of
      (r : _) -> Just r
      [] -> Nothing
    exact s e = texprType e == s && not (isIntLiteral e) && not (isWidened e) && wellFormed e
    operand s e = texprType e == s && wellFormed e
    pair s a b =
      operand s a && operand s b
        && not (isOpenLit a && isOpenLit b)
        && not (isWidened a && isWidened b)
        -- MT-CONST-3: a REAL literal next to a widened INT is rejected
        && not (isOpenLit a && isWidened b)
        && not (isWidened a && isOpenLit b)
    litOk t = \case
      LitInt n _ -> let (lo, hi) = literalRange t in t /= BOOL && n >= lo && n <= hi
      LitReal _ -> t == REAL
      LitBool _ -> t == BOOL

-- | Smaller expressions of the same type, valid wherever the original was
-- (the caller filters with its own position rules).
shrinkTExpr :: TExpr -> [TExpr]
shrinkTExpr e = filter wellFormed (replacements ++ inside)
  where
    t = texprType e
    zeroLit = case t of
      BOOL -> TLit BOOL (LitBool False)
      REAL -> TLit REAL (LitReal 0)
      _ -> TLit t (LitInt 0 10)
    replacements =
      [zeroLit | e /= zeroLit, not (isLeaf e)]
        ++ [c | c <- children, texprType c == t, not (isWidened c)]
        ++ case e of
          TLit ty (LitInt n b) -> [TLit ty (LitInt m b) | m <- shrinkIntegral n]
          TLit ty (LitReal r) -> [TLit ty (LitReal x) | x <- [0, 1, fromIntegral (truncate r :: Integer)], realBits x /= realBits r, abs x < abs r]
          TLit ty (LitBool True) -> [TLit ty (LitBool False)]
          _ -> []
    isLeaf = \case
      TLit {} -> True
      TVar {} -> True
      TFlag -> True
      _ -> False
    children = case e of
      TWiden _ _ a -> [a]
      TConv _ _ a -> [a]
      TNeg _ a -> [a]
      TNot _ a -> [a]
      TArith _ _ a b -> [a, b]
      TCmp _ _ a b -> [a, b]
      TLogic _ _ a b -> [a, b]
      TExpt _ a b -> [a, b]
      TCall _ _ as -> as
      TIndex _ _ i -> [i]
      _ -> []
    inside = case e of
      TWiden s ty a -> TWiden s ty <$> shrinkTExpr a
      TConv s ty a -> TConv s ty <$> shrinkTExpr a
      TNeg ty a -> TNeg ty <$> shrinkTExpr a
      TNot ty a -> TNot ty <$> shrinkTExpr a
      TArith op ty a b -> [TArith op ty a' b | a' <- shrinkTExpr a] ++ [TArith op ty a b' | b' <- shrinkTExpr b]
      TCmp op ty a b -> [TCmp op ty a' b | a' <- shrinkTExpr a] ++ [TCmp op ty a b' | b' <- shrinkTExpr b]
      TLogic op ty a b -> [TLogic op ty a' b | a' <- shrinkTExpr a] ++ [TLogic op ty a b' | b' <- shrinkTExpr b]
      TExpt ty a b -> [TExpt ty a' b | a' <- shrinkTExpr a] ++ [TExpt ty a b' | b' <- shrinkTExpr b]
      TCall ty f as -> TCall ty f <$> shrinkEach as
      TIndex ty a i -> TIndex ty a <$> shrinkTExpr i
      _ -> []
    shrinkEach = \case
      [] -> []
      (a : as) -> [a' : as | a' <- shrinkTExpr a] ++ map (a :) (shrinkEach as)

------------------------------------------------------------------------------
-- Statements and modules

-- | Statements, with the loop shapes that guarantee termination.
data GStmt
  = GAssign Text BasicType TExpr -- ^ target, its type, value of that type (possibly widened or a literal)
  | GAssignIndex Text BasicType TExpr TExpr -- ^ array, element type, index, value
  | GCall Text [TExpr] -- ^ a function call as a statement (MT-STMT-3)
  | GIf [(TExpr, [GStmt])] (Maybe [GStmt])
  | GCase TExpr [([(Integer, Integer)], [GStmt])] (Maybe [GStmt]) -- ^ selector of an ANY_INT type, label ranges
  | GFor Text BasicType Integer Integer (Maybe Integer) [GStmt] -- ^ control variable, type, start, end, BY
  | GForVar Text BasicType Integer Text Integer (Maybe Integer) [GStmt]
  -- ^ @e := k; FOR cv := start TO e BY step DO body END_FOR;@ where the body
  -- may change @e@ (policy for-bounds)
  | GWhile Text Integer TExpr [GStmt] -- ^ counter, bound: @c := 0; WHILE c < k AND cond DO body c := c + 1; END_WHILE;@
  | GRepeat Text Integer TExpr [GStmt] -- ^ @c := 0; REPEAT body c := c + 1; UNTIL c >= k OR cond END_REPEAT;@
  | GExit
  | GReturn
  | GEmpty
  deriving (Eq, Show)

data LocalVar = LocalVar {lvName :: Text, lvType :: BasicType, lvInit :: Maybe Lit}
  deriving (Eq, Show)

data GFunction = GFunction
  { gfName :: Text
  , gfResult :: BasicType
  , gfParams :: [(Text, BasicType)]
  , gfLocals :: [LocalVar]
  , gfBody :: [GStmt] -- ^ starts with an assignment of the result (MT-POU-4)
  }
  deriving (Eq, Show)

data GProgram = GProgram {gpLocals :: [LocalVar], gpBody :: [GStmt]}
  deriving (Eq, Show)

-- | A global array mapped onto consecutive operands (MT-MAP-9): element k
-- is the operand k - lower after the first.
data GArray = GArray {gaName :: Text, gaType :: BasicType, gaLower :: Integer, gaUpper :: Integer, gaFirst :: Operand}
  deriving (Eq, Show)

arrayOperands :: GArray -> [Operand]
arrayOperands a = [shift (fromInteger (k - gaLower a)) | k <- [gaLower a .. gaUpper a]]
  where
    shift d = case gaFirst a of
      OpSimple kind n -> OpSimple kind (n + d)
      OpTablePos kind n p -> OpTablePos kind n (p + d)
      op -> op

-- | An index for the array: mostly a literal within the bounds, sometimes
-- just outside them (runtime error 2015), sometimes any ANY_INT expression.
genIndex :: Scope -> GArray -> Gen TExpr
genIndex sc a =
  frequency
    [ (12, TLit DINT . (`LitInt` 10) <$> choose (gaLower a, gaUpper a))
    , (1, TLit DINT . (`LitInt` 10) <$> elements [gaLower a - 1, gaUpper a + 1])
    , (1, elements [USINT, INT, DINT] >>= \t -> resize 2 (genExactExpr sc {scArrays = []} t))
    ]

-- | A global mapped onto a PLC operand (MT-MAP-4, Table 4-8).
data MappedVar = MappedVar {mvName :: Text, mvType :: BasicType, mvOperand :: Operand}
  deriving (Eq, Show)

data GenModule = GenModule
  { gmMapped :: [MappedVar]
  , gmArrays :: [GArray] -- ^ mapped arrays (MT-MAP-9)
  , gmGlobals :: [LocalVar] -- ^ unmapped globals
  , gmInputs :: [(Operand, Value)] -- ^ operand values before the call
  , gmFunctions :: [GFunction]
  , gmProgram :: GProgram
  }
  deriving (Eq, Show)

data GenConfig = GenConfig
  { gcFunctions :: Int -- ^ at most this many functions
  , gcStatements :: Int -- ^ at most this many statements per list
  , gcTypeMaxFor :: Bool -- ^ allow FOR loops that end at the type's maximum (policy for-at-type-max)
  , gcShadowing :: Bool -- ^ declare program locals with globals' names (policy name-resolution)
  , gcFlag :: Bool -- ^ read INTERNAL_OVERFLOW in the program
  , gcNegativeReals :: Bool -- ^ write negative REAL literals
  , gcVariableForBounds :: Bool -- ^ FOR loops whose end is a variable the body may change (policy for-bounds)
  }
  deriving (Show)

defaultGenConfig :: GenConfig
defaultGenConfig = GenConfig {gcFunctions = 3, gcStatements = 5, gcTypeMaxFor = False, gcShadowing = False, gcFlag = True, gcNegativeReals = True, gcVariableForBounds = False}

-- | Mapped arrays (never BOOL, MT-MAP-11) at operands of the default
-- configuration, clear of the scalars: zero to two of them.
genArrays :: Gen [GArray]
genArrays = do
  k <- choose (0, 2)
  kinds <- take k <$> shuffle [("GAI", INT, OpSimple KM 200), ("GAD", DINT, OpSimple KI 50), ("GAR", REAL, OpSimple KF 50), ("GAU", USINT, OpSimple KA 40), ("GAW", WORD, OpSimple KM 220)]
  mapM (\(n, t, o) -> do lo <- choose (0, 5); len <- choose (1, 6); pure (GArray n t lo (lo + len - 1) o)) kinds

-- | Mapped globals: two of each type, at operands of the default
-- configuration (defaultPlcConfig), none aliasing another.
standardMapped :: [MappedVar]
standardMapped = concatMap forType allBasicTypes
  where
    forType t = [MappedVar (prefix t <> T.pack (show i)) t (operand t i) | i <- [0, 1 :: Int]]
    prefix = \case
      BOOL -> "GX"
      BYTE -> "GB"
      WORD -> "GW"
      DWORD -> "GDW"
      USINT -> "GU"
      INT -> "GI"
      DINT -> "GD"
      REAL -> "GR"
    operand t i = case t of
      BOOL -> OpBit KM 500 i
      BYTE -> OpSimple KA (10 + i)
      USINT -> OpSimple KA (20 + i)
      WORD -> OpSimple KM (100 + i)
      INT -> OpSimple KM (110 + i)
      DWORD -> OpSimple KI (10 + i)
      DINT -> OpSimple KI (20 + i)
      REAL -> OpSimple KF (10 + i)

-- | A state threaded through statement generation: fresh loop names.
data Ctx = Ctx
  { cxScope :: Scope
  , cxTargets :: [(Text, BasicType)] -- ^ writable variables
  , cxArrayTargets :: [GArray] -- ^ writable arrays
  , cxInLoop :: Bool
  , cxLoopDepth :: Int
  , cxNesting :: Int -- ^ depth of compound statements
  , cxPrefix :: Text -- ^ for fresh names of loop variables
  , cxConfig :: GenConfig
  }

genModule :: GenConfig -> Gen GenModule
genModule cfg = do
  let mapped = standardMapped
      globalScope = [(mvName v, mvType v) | v <- mapped]
  nGlobals <- choose (0, 3)
  globals <- mapM (\i -> genLocal ("GL" <> T.pack (show i))) [0 .. nGlobals - 1 :: Int]
  arrays <- genArrays
  inputs <-
    (++)
      <$> mapM (\v -> (mvOperand v,) <$> genValue (mvType v)) mapped
      <*> mapM (\(o, t) -> (o,) <$> genValue t) [(o, gaType a) | a <- arrays, o <- arrayOperands a]
  nFun <- choose (0, gcFunctions cfg)
  funs <- genFunctions cfg (globalScope ++ [(lvName g, lvType g) | g <- globals]) nFun
  let funSigs = [(gfName f, gfResult f, map snd (gfParams f)) | f <- funs]
  nLocals <- choose (0, 3)
  locals0 <- mapM (\i -> genLocal ("PL" <> T.pack (show i))) [0 .. nLocals - 1 :: Int]
  shadow <-
    if gcShadowing cfg
      then do
        vs <- sublistOf mapped
        mapM (\v -> (\i -> LocalVar (mvName v) (mvType v) (Just i)) <$> genLiteral (mvType v)) (take 3 vs)
      else pure []
  let locals = locals0 ++ shadow
      readable = globalScope ++ [(lvName g, lvType g) | g <- globals] ++ [(lvName l, lvType l) | l <- locals0]
      signals = [("INPUT" <> T.pack (show i), BOOL) | i <- [1 .. 3 :: Int]]
      outputs = [("OUTPUT" <> T.pack (show i), BOOL) | i <- [1 .. 3 :: Int]]
      ctx =
        Ctx
          { cxScope = Scope (readable ++ signals) (gcFlag cfg) funSigs arrays (gcNegativeReals cfg)
          , cxTargets = readable ++ outputs
          , cxArrayTargets = arrays
          , cxInLoop = False
          , cxLoopDepth = 0
          , cxNesting = 0
          , cxPrefix = "P"
          , cxConfig = cfg
          }
  body <- genBody ctx True
  pure (GenModule mapped arrays globals inputs funs (GProgram locals body))

genLocal :: Text -> Gen LocalVar
genLocal name = do
  t <- elements allBasicTypes
  i <- frequency [(1, pure Nothing), (2, Just <$> genLiteral t)]
  pure (LocalVar name t i)

genFunctions :: GenConfig -> [(Text, BasicType)] -> Int -> Gen [GFunction]
genFunctions cfg globals n = go 0 []
  where
    go i acc
      | i >= n = pure (reverse acc)
      | otherwise = do
          let name = "FN" <> T.pack (show i)
              earlier = [(gfName f, gfResult f, map snd (gfParams f)) | f <- reverse acc]
          result <- elements allBasicTypes
          np <- choose (1, 3)
          params <- mapM (\k -> (name <> "_A" <> T.pack (show k),) <$> elements allBasicTypes) [0 .. np - 1 :: Int]
          nl <- choose (0, 2)
          locals <- mapM (\k -> genLocal (name <> "_L" <> T.pack (show k))) [0 .. nl - 1 :: Int]
          let readable = globals ++ params ++ [(lvName l, lvType l) | l <- locals]
              ctx =
                Ctx
                  { cxScope = Scope readable False earlier [] (gcNegativeReals cfg)
                  , cxTargets = [(lvName l, lvType l) | l <- locals]
                  , cxArrayTargets = []
                  , cxInLoop = False
                  , cxLoopDepth = 0
                  , cxNesting = 0
                  , cxPrefix = name <> "_"
                  , cxConfig = cfg
                  }
          first <- GAssign name result <$> scaled (genExpr (cxScope ctx) result)
          rest <- genBody ctx {cxTargets = cxTargets ctx ++ [(name, result)]} True
          go (i + 1) (GFunction name result params locals (first : rest) : acc)

scaled :: Gen a -> Gen a
scaled = scale (\s -> min 8 (s `div` 8 + 1))

-- | A statement list; @final@ allows a closing RETURN/EXIT (never followed
-- by anything, MT-STMT-22).
genBody :: Ctx -> Bool -> Gen [GStmt]
genBody ctx final = do
  k <- choose (1, gcStatements (cxConfig ctx))
  stmts <- mapM (\i -> genStmt ctx {cxPrefix = cxPrefix ctx <> T.pack (show i) <> "_"}) [0 .. k - 1 :: Int]
  end <- frequency [(8, pure []), (1, pure [GReturn | final]), (1, pure [GExit | final, cxInLoop ctx])]
  pure (stmts ++ end)

genStmt :: Ctx -> Gen GStmt
genStmt ctx =
  frequency $
    [(6, assign)]
      ++ [(1, callStmt) | not (null (scFunctions sc))]
      ++ [(2, ifStmt) | shallow]
      ++ [(1, caseStmt) | shallow]
      ++ [(1, forStmt) | deep]
      ++ [(2, forVarStmt) | deep, gcVariableForBounds (cxConfig ctx)]
      ++ [(1, whileStmt) | deep]
      ++ [(1, repeatStmt) | deep]
      ++ [(1, pure GEmpty)]
  where
    sc = cxScope ctx
    deep = cxLoopDepth ctx < 2 && shallow
    shallow = cxNesting ctx < 3
    arm :: Int -> Ctx
    arm i = ctx {cxPrefix = cxPrefix ctx <> "A" <> T.pack (show i) <> "_"}
    nested = ctx {cxLoopDepth = cxLoopDepth ctx + 1, cxInLoop = True}
    smallBody c = smallBodyEnding c True
    -- a WHILE or REPEAT body is followed by its counter's increment, so it
    -- may not end with EXIT or RETURN itself (MT-STMT-22)
    smallBodyEnding c final = resize 2 (genBody c {cxNesting = cxNesting c + 1, cxConfig = (cxConfig c) {gcStatements = min 3 (gcStatements (cxConfig c))}} final)
    assign =
      frequency $
        [ (4, do (v, t) <- elements (cxTargets ctx); GAssign v t <$> scaled (genExpr sc t))
        ]
          ++ [ ( 1
               , do
                   a <- elements (cxArrayTargets ctx)
                   GAssignIndex (gaName a) (gaType a) <$> genIndex sc a <*> scaled (genExpr sc (gaType a))
               )
             | not (null (cxArrayTargets ctx))
             ]
    callStmt = do
      (f, _, ps) <- elements (scFunctions sc)
      GCall f <$> mapM (scaled . genExpr sc) ps
    ifStmt = do
      n <- choose (1, 3)
      arms <- mapM (\i -> (,) <$> scaled (genExactExpr sc BOOL) <*> smallBody (arm i)) [0 .. n - 1]
      els <- frequency [(1, pure Nothing), (1, Just <$> smallBody (arm n))]
      pure (GIf arms els)
    caseStmt = do
      s <- elements [USINT, INT, DINT]
      sel <- scaled (genExactExpr sc s)
      let (lo, hi) = literalRange s
      starts <- nub <$> replicateM 4 (frequency [(3, choose (max lo (-5), min hi 10)), (1, choose (lo, hi))])
      arms <- mapM (\(i, a) -> (\w b -> ([(a, min hi (a + w))], b)) <$> elements [0, 0, 0, 2] <*> smallBody (arm i)) (zip [0 ..] starts)
      els <- frequency [(1, pure Nothing), (1, Just <$> smallBody (arm (length starts)))]
      pure (GCase sel (disjoint arms) els)
    forStmt = do
      t <- elements [USINT, INT]
      let cv = cxPrefix ctx <> "FC"
      (start, end, step) <- genForBounds t
      body <- smallBody nested {cxScope = sc {scVars = (cv, t) : scVars sc}}
      pure (GFor cv t start end step body)
    forVarStmt = do
      t <- elements [USINT, INT]
      let cv = cxPrefix ctx <> "FC"
          e = cxPrefix ctx <> "FE"
      start <- choose (0, 3)
      end <- choose (0, 6)
      step <- frequency [(2, pure Nothing), (1, Just <$> choose (1, 2))]
      let inner = nested {cxScope = sc {scVars = (cv, t) : (e, t) : scVars sc}, cxTargets = (e, t) : cxTargets ctx}
      body <- smallBody inner
      change <-
        elements
          [ TArith OpSub t (TVar t e) (TLit t (LitInt 1 10))
          , TArith OpAdd t (TVar t e) (TLit t (LitInt 1 10))
          , TLit t (LitInt 2 10)
          ]
      -- the body changes the end variable before anything may leave the loop
      pure (GForVar cv t start e end step (GAssign e t change : body))
    whileStmt = do
      let c = cxPrefix ctx <> "WC"
      k <- choose (0, 4)
      cond <- scaled (genExactExpr sc BOOL)
      GWhile c k cond <$> smallBodyEnding nested False
    repeatStmt = do
      let c = cxPrefix ctx <> "RC"
      k <- choose (1, 4)
      cond <- scaled (genExactExpr sc BOOL)
      GRepeat c k cond <$> smallBodyEnding nested False
    genForBounds t = do
      let typeMax = if t == USINT then 255 else 32767
      atMax <- if gcTypeMaxFor (cxConfig ctx) then frequency [(1, pure True), (2, pure False)] else pure False
      if atMax
        then do
          start <- choose (typeMax - 5, typeMax)
          pure (start, typeMax, Nothing)
        else do
          let lo = if t == USINT then 0 else -10
          start <- choose (lo, 10)
          end <- choose (lo, 12)
          step <- frequency [(2, pure Nothing), (2, Just <$> choose (1, 3)), (1, if t == INT then Just <$> choose (-3, -1) else pure Nothing)]
          pure (start, end, step)

-- | Keep only arms whose labels do not overlap earlier ones (MT-STMT-10).
disjoint :: [([(Integer, Integer)], a)] -> [([(Integer, Integer)], a)]
disjoint = go []
  where
    go _ [] = []
    go seen ((rs, b) : rest)
      | any (\(a, z) -> any (\(a', z') -> a <= z' && a' <= z) seen) rs = go seen rest
      | otherwise = (rs, b) : go (rs ++ seen) rest

------------------------------------------------------------------------------
-- Shrinking

shrinkGenModule :: GenModule -> [GenModule]
shrinkGenModule gm =
  [gm {gmFunctions = fs} | fs <- dropUnusedFunction]
    ++ [gm {gmMapped = vs, gmInputs = [(o, x) | (o, x) <- gmInputs gm, o `elem` map mvOperand vs]} | vs <- dropUnused mvName (gmMapped gm)]
    ++ [gm {gmArrays = as, gmInputs = [(o, x) | (o, x) <- gmInputs gm, o `notElem` concatMap arrayOperands (gmArrays gm \\ as)]} | as <- dropUnused gaName (gmArrays gm)]
    ++ [gm {gmGlobals = ls} | ls <- dropUnused lvName (gmGlobals gm)]
    ++ [gm {gmProgram = (gmProgram gm) {gpLocals = ls}} | ls <- dropUnused lvName (gpLocals (gmProgram gm))]
    ++ [gm {gmFunctions = fs} | fs <- dropUnusedLocals (gmFunctions gm)]
    ++ [gm {gmProgram = (gmProgram gm) {gpBody = b}} | b <- shrinkBody False (gpBody (gmProgram gm))]
    ++ [gm {gmFunctions = fs} | fs <- shrinkFunctions (gmFunctions gm)]
    ++ [gm {gmInputs = is} | is <- shrinkInputs (gmInputs gm)]
  where
    used = usedNames gm
    -- all unused ones at once (one step), so that shrinking stays cheap
    dropUnused name xs = [kept | let kept = filter ((`elem` used) . name) xs, length kept < length xs]
    dropUnusedLocals = \case
      [] -> []
      (f : fs) ->
        [f {gfLocals = ls} : fs | ls <- dropUnused lvName (gfLocals f)]
          ++ map (f :) (dropUnusedLocals fs)
    dropUnusedFunction =
      [ take i fs ++ drop (i + 1) fs
      | let fs = gmFunctions gm
      , (i, f) <- zip [0 ..] fs
      , not (gfName f `elem` calledNames gm)
      ]
    shrinkFunctions = \case
      [] -> []
      (f : fs) ->
        [f {gfBody = b} : fs | b <- shrinkFunctionBody f]
          ++ map (f :) (shrinkFunctions fs)
    shrinkFunctionBody f = case gfBody f of
      (GAssign v t e : rest) ->
        [GAssign v t e' : rest | e' <- shrinkTExpr e]
          ++ [GAssign v t e : rest' | rest' <- shrinkBody True rest]
      body -> shrinkBody True body
    shrinkInputs = \case
      [] -> []
      ((o, v) : rest) -> [(o, v') : rest | v' <- shrinkValue v] ++ map ((o, v) :) (shrinkInputs rest)

-- | Shrink a statement list: drop a statement, inline an IF branch, shrink
-- inside. @emptyOk@: may the list become empty (function bodies keep their
-- first statement elsewhere)?
shrinkBody :: Bool -> [GStmt] -> [[GStmt]]
shrinkBody emptyOk stmts =
  [nonEmpty ss | ss <- removals, validList ss]
    ++ [ss | ss <- inlined, validList ss]
    ++ [ss | ss <- insides, validList ss]
  where
    nonEmpty ss = if null ss && not emptyOk then [GEmpty] else ss
    removals = [take i stmts ++ drop (i + 1) stmts | i <- [0 .. length stmts - 1], stmts /= [GEmpty]]
    inlined =
      [ take i stmts ++ branch ++ drop (i + 1) stmts
      | (i, s) <- zip [0 ..] stmts
      , branch <- branchesOf s
      , not (any endsFlow branch)
      ]
    insides = [take i stmts ++ [s'] ++ drop (i + 1) stmts | (i, s) <- zip [0 ..] stmts, s' <- shrinkStmt s]
    validList ss = not (any endsFlow (safeInit ss))
    safeInit xs = if null xs then [] else init xs
    endsFlow = \case
      GExit -> True
      GReturn -> True
      _ -> False
    branchesOf = \case
      GIf arms els -> map snd arms ++ maybe [] pure els
      GCase _ arms els -> map snd arms ++ maybe [] pure els
      -- a loop's body alone, when it neither leaves the loop nor reads the
      -- control variable
      GFor cv _ _ _ _ b | not (exitsLoop b), cv `notElem` namesIn b -> [b]
      GWhile _ _ _ b | not (exitsLoop b) -> [b]
      GRepeat _ _ _ b | not (exitsLoop b) -> [b]
      _ -> []
    namesIn b = usedNames (GenModule [] [] [] [] [] (GProgram [] b))
    exitsLoop = any $ \case
      GExit -> True
      GIf arms els -> any (exitsLoop . snd) arms || maybe False exitsLoop els
      GCase _ arms els -> any (exitsLoop . snd) arms || maybe False exitsLoop els
      _ -> False

shrinkStmt :: GStmt -> [GStmt]
shrinkStmt = \case
  GAssign v t e -> GAssign v t <$> shrinkTExpr e
  GAssignIndex a t i e -> [GAssignIndex a t i' e | i' <- shrinkTExpr i] ++ [GAssignIndex a t i e' | e' <- shrinkTExpr e]
  GCall f args -> [GCall f (take i args ++ [a'] ++ drop (i + 1) args) | (i, a) <- zip [0 ..] args, a' <- shrinkTExpr a]
  GIf arms els ->
    [GIf (take i arms ++ drop (i + 1) arms) els | length arms > 1, i <- [0 .. length arms - 1]]
      ++ [GIf arms Nothing | isJust els]
      ++ [GIf (replaceAt i (c', b) arms) els | (i, (c, b)) <- zip [0 ..] arms, c' <- shrinkTExpr c, exactDefinite BOOL c']
      ++ [GIf (replaceAt i (c, b') arms) els | (i, (c, b)) <- zip [0 ..] arms, b' <- shrinkBody True b]
      ++ [GIf arms (Just b') | Just b <- [els], b' <- shrinkBody True b]
  GCase sel arms els ->
    [GCase sel (take i arms ++ drop (i + 1) arms) els | i <- [0 .. length arms - 1]]
      ++ [GCase sel arms Nothing | isJust els]
      ++ [GCase sel' arms els | sel' <- shrinkTExpr sel, exactDefinite (texprType sel) sel']
      ++ [GCase sel (replaceAt i (l, b') arms) els | (i, (l, b)) <- zip [0 ..] arms, b' <- shrinkBody True b]
  GForVar cv t s e k st body ->
    [GForVar cv t s e k' st body | k' <- shrinkIntegral k, k' >= 0]
      ++ [GForVar cv t s e k Nothing body | isJust st]
      ++ [GForVar cv t s e k st body' | body' <- shrinkBody True body]
  GFor cv t s e st body ->
    [GFor cv t s e' st body | e' <- [s, s + 1], e' /= e, e' < e]
      ++ [GFor cv t s e Nothing body | isJust st]
      ++ [GFor cv t s e st body' | body' <- shrinkBody True body]
  GWhile c k cond body ->
    [GWhile c k' cond body | k' <- shrinkIntegral k, k' >= 0]
      ++ [GWhile c k cond' body | cond' <- shrinkTExpr cond, exactDefinite BOOL cond']
      ++ [GWhile c k cond body' | body' <- shrinkBody True body]
  GRepeat c k cond body ->
    [GRepeat c k' cond body | k' <- shrinkIntegral k, k' >= 1]
      ++ [GRepeat c k cond' body | cond' <- shrinkTExpr cond, exactDefinite BOOL cond']
      ++ [GRepeat c k cond body' | body' <- shrinkBody True body]
  _ -> []
  where
    replaceAt i x xs = take i xs ++ [x] ++ drop (i + 1) xs
    exactDefinite t e = texprType e == t && not (isIntLiteral e) && not (isWidened e)

-- | A name as a statement or expression mentions it: a variable (read,
-- written or indexed) or a called function.
data Mention = Variable Text | Called Text

mentionName :: Mention -> Text
mentionName = \case
  Variable v -> v
  Called f -> f

-- | Every mention in a module's bodies, in one walk (the functions' first).
moduleMentions :: GenModule -> [Mention]
moduleMentions gm = concatMap (concatMap stmtMentions . gfBody) (gmFunctions gm) ++ concatMap stmtMentions (gpBody (gmProgram gm))

stmtMentions :: GStmt -> [Mention]
stmtMentions = \case
  GAssign v _ e -> Variable v : exprMentions e
  GAssignIndex a _ i e -> Variable a : exprMentions i ++ exprMentions e
  GCall f args -> Called f : concatMap exprMentions args
  GIf arms els -> concat [exprMentions c ++ body b | (c, b) <- arms] ++ maybe [] body els
  GCase sel arms els -> exprMentions sel ++ concatMap (body . snd) arms ++ maybe [] body els
  GFor _ _ _ _ _ b -> body b
  GForVar _ _ _ e _ _ b -> Variable e : body b
  GWhile _ _ c b -> exprMentions c ++ body b
  GRepeat _ _ c b -> exprMentions c ++ body b
  _ -> []
  where
    body = concatMap stmtMentions

exprMentions :: TExpr -> [Mention]
exprMentions = \case
  TVar _ v -> [Variable v]
  TCall _ f args -> Called f : concatMap exprMentions args
  TIndex _ a i -> Variable a : exprMentions i
  TWiden _ _ e -> exprMentions e
  TConv _ _ e -> exprMentions e
  TNeg _ e -> exprMentions e
  TNot _ e -> exprMentions e
  TArith _ _ a b -> exprMentions a ++ exprMentions b
  TCmp _ _ a b -> exprMentions a ++ exprMentions b
  TLogic _ _ a b -> exprMentions a ++ exprMentions b
  TExpt _ a b -> exprMentions a ++ exprMentions b
  _ -> []

-- | Every name read, written or called anywhere in the module.
usedNames :: GenModule -> [Text]
usedNames = nub . map mentionName . moduleMentions

-- | Names of the functions called anywhere in the module.
calledNames :: GenModule -> [Text]
calledNames gm = [f | Called f <- moduleMentions gm]

-- | Does the program call any function?
moduleUsesCalls :: GenModule -> Bool
moduleUsesCalls = not . null . calledNames

------------------------------------------------------------------------------
-- To the syntax tree

toModule :: GenModule -> Module ()
toModule gm =
  Module
    { modGlobals =
        [VarBlock () SecVar False (map mappedDecl (gmMapped gm) ++ map arrayDecl (gmArrays gm)) | not (null (gmMapped gm) && null (gmArrays gm))]
          ++ [VarBlock () SecVar False (map localDecl (gmGlobals gm)) | not (null (gmGlobals gm))]
    , modFunctions = map function (gmFunctions gm)
    , modProgram =
        Program () (Ident "EXPLORE") (localBlock (gpLocals (gmProgram gm)) (loopVars (gpBody (gmProgram gm)))) (concatMap stmt (gpBody (gmProgram gm)))
    }
  where
    arrayDecl a = VarDecl () [((), Ident (gaName a))] (Just ((), operandRef (gaFirst a))) (TArray (bound (gaLower a)) (bound (gaUpper a)) (gaType a)) Nothing
    bound n = toExpr (TLit DINT (LitInt n 10))
    mappedDecl v = VarDecl () [((), Ident (mvName v))] (Just ((), operandRef (mvOperand v))) (TBasic (mvType v)) Nothing
    localDecl l = VarDecl () [((), Ident (lvName l))] Nothing (TBasic (lvType l)) (InitExpr . toExpr . TLit (lvType l) <$> lvInit l)
    loopDecl (n, t) = VarDecl () [((), Ident n)] Nothing (TBasic t) Nothing
    localBlock ls lvs = [VarBlock () SecVar False (map localDecl ls ++ map loopDecl lvs) | not (null ls && null lvs)]
    function f =
      Function
        { fnAnn = ()
        , fnName = Ident (gfName f)
        , fnResult = gfResult f
        , fnBlocks =
            VarBlock () SecInput False [VarDecl () [((), Ident p)] Nothing (TBasic t) Nothing | (p, t) <- gfParams f]
              : localBlock (gfLocals f) (loopVars (gfBody f))
        , fnBody = concatMap stmt (gfBody f)
        }

-- | The loop counters and control variables a body uses, to declare them.
loopVars :: [GStmt] -> [(Text, BasicType)]
loopVars = nub . concatMap go
  where
    go = \case
      GIf arms els -> concatMap (loopVars . snd) arms ++ maybe [] loopVars els
      GCase _ arms els -> concatMap (loopVars . snd) arms ++ maybe [] loopVars els
      GFor cv t _ _ _ b -> (cv, t) : loopVars b
      GForVar cv t _ e _ _ b -> (cv, t) : (e, t) : loopVars b
      GWhile c _ _ b -> (c, INT) : loopVars b
      GRepeat c _ _ b -> (c, INT) : loopVars b
      _ -> []

operandRef :: Operand -> OperandRef
operandRef = \case
  OpSimple k a -> OperandRef (simpleLetter k) (toInteger a) NoSub
  OpBit k a b -> OperandRef (simpleLetter k) (toInteger a) (BitOf (toInteger b))
  OpTablePos k a p -> OperandRef (tableLetters k) (toInteger a) (Position (toInteger p))

stmt :: GStmt -> [Stmt ()]
stmt = \case
  GAssign v _ e -> [Assign () (LVar () (Ident v)) (toExpr e)]
  GAssignIndex a _ i e -> [Assign () (LIndex () (Ident a) (toExpr i)) (toExpr e)]
  GCall f args -> [CallStmt () (Ident f) (map toExpr args)]
  GIf arms els -> [If () [(toExpr c, body b) | (c, b) <- arms] (body <$> els)]
  GCase sel arms els -> [Case () (toExpr sel) [CaseArm () (map label ls) (body b) | (ls, b) <- arms] (body <$> els)]
  GFor cv t s e st b -> [For () ((), Ident cv) (intLit t s) (intLit t e) (intLit t <$> st) (body b)]
  GForVar cv t s e k st b ->
    [ Assign () (LVar () (Ident e)) (intLit t k)
    , For () ((), Ident cv) (intLit t s) (var e) (intLit t <$> st) (body b)
    ]
  GWhile c k cond b ->
    [ assignInt c 0
    , While () (EBinary () And (EBinary () Lt (var c) (intLit INT k)) (toExpr cond)) (body b ++ [increment c])
    ]
  GRepeat c k cond b ->
    [ assignInt c 0
    , Repeat () (body b ++ [increment c]) (EBinary () Or (EBinary () Ge (var c) (intLit INT k)) (toExpr cond))
    ]
  GExit -> [Exit ()]
  GReturn -> [Return ()]
  GEmpty -> [Empty ()]
  where
    body = concatMap stmt
    var c = EVar () (Ident c)
    intLit t n = toExpr (TLit t (LitInt n 10))
    label (lo, hi)
      | lo == hi = LabelValue (intLit DINT lo)
      | otherwise = LabelRange (intLit DINT lo) (intLit DINT hi)
    assignInt c n = Assign () (LVar () (Ident c)) (intLit INT n)
    increment c = Assign () (LVar () (Ident c)) (EBinary () Add (var c) (intLit INT 1))

-- | The operands whose final values are the outcome of a run.
observedOperands :: GenModule -> [Operand]
observedOperands gm = map mvOperand (gmMapped gm) ++ concatMap arrayOperands (gmArrays gm)

-- | The controller memory before the call.
initialMemory :: GenModule -> Memory
initialMemory gm = foldl (\m (o, v) -> writeOperand o v m) emptyMemory (gmInputs gm)

-- | Run a generator with an explicit seed and size: the same seed gives the
-- same value (for @stref explore --seed@).
generateWithSeed :: Int -> Int -> Gen a -> a
generateWithSeed seed size g = unGen g (mkQCGen seed) size
