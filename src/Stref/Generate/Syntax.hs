-- | QuickCheck generators of syntax trees: lexically valid (legal, unreserved
-- names; literals the lexer can read; shapes the grammar can express) but
-- not necessarily well typed. They feed the print/parse round trip.
module Stref.Generate.Syntax
  ( genModule
  , genExpr
  , genStmts
  , genIdent
  , genLiteral
  ) where

import qualified Data.Text as T
import Stref.Lexical (isPlainName)
import Stref.Policy (mastertoolXE)
import Stref.Syntax
import Stref.Types (allBasicTypes)
import Test.QuickCheck

-- | A legal name that is not reserved under the MasterTool preset: segments
-- of letters and digits joined by single '_', possibly starting with '_'.
genIdent :: Gen Ident
genIdent = (Ident <$> candidate) `suchThat` (isPlainName mastertoolXE . identText)
  where
    candidate = do
      lead <- frequency [(1, pure "_"), (6, pure "")]
      first <- if lead == "" then elements letters else elements (letters ++ digits)
      restOfFirst <- resize 6 (listOf (elements (letters ++ digits)))
      more <- resize 2 (listOf (resize 4 (listOf1 (elements (letters ++ digits)))))
      pure (T.pack (lead ++ [first] ++ restOfFirst ++ concatMap ('_' :) more))
    letters = ['a' .. 'z'] ++ ['A' .. 'Z']
    digits = ['0' .. '9']

-- | Names used as variables: sometimes a predeclared one.
genVarName :: Gen Ident
genVarName = frequency [(12, genIdent), (1, elements (map Ident ["INPUT1", "OUTPUT2", "INTERNAL_OVERFLOW"]))]

-- | Names used as called functions: sometimes a conversion, EXPT or a
-- reserved standard function (the checker rejects those, the parser not).
genCallName :: Gen Ident
genCallName = frequency [(10, genIdent), (1, elements (map Ident ["EXPT", "INT_TO_REAL", "ANY_TO_DINT", "ABS"]))]

-- | Non-negative literals (a sign is an operator, MT-LEX-19); reals with a
-- finite decimal expansion, as every real literal has.
genLiteral :: Gen Literal
genLiteral =
  oneof
    [ LInt <$> genNat <*> elements [10, 10, 2, 8, 16]
    , LReal <$> genReal
    , LBool <$> arbitrary
    ]
  where
    genNat = frequency [(4, choose (0, 1000)), (2, choose (0, 2 ^ (32 :: Int))), (1, choose (0, 10 ^ (30 :: Int)))]
    genReal = do
      mantissa <- choose (0, 10 ^ (9 :: Int)) :: Gen Integer
      scale <- choose (0, 9) :: Gen Integer
      expo <- frequency [(5, pure 0), (1, choose (-40, 40))] :: Gen Integer
      pure (fromInteger mantissa / 10 ^ scale * 10 ^^ expo)

genExpr :: Int -> Gen (Expr ())
genExpr n
  | n <= 0 = atom
  | otherwise =
      frequency
        [ (2, atom)
        , (5, EBinary () <$> arbitraryBoundedEnum <*> sub <*> sub)
        , (2, EUnary () <$> arbitraryBoundedEnum <*> sub)
        , (1, ECall () <$> genCallName <*> resize 3 (listOf sub))
        , (1, EIndex () <$> genVarName <*> sub)
        ]
  where
    sub = genExpr (n `div` 2)
    atom = frequency [(3, ELit () <$> genLiteral), (3, EVar () <$> genVarName)]

genStmts :: Int -> Gen [Stmt ()]
genStmts n = resize 4 (listOf (genStmt n))

genStmt :: Int -> Gen (Stmt ())
genStmt n
  | n <= 0 = simple
  | otherwise =
      frequency
        [ (4, simple)
        , (1, If () <$> resize 3 (listOf1 ((,) <$> expr <*> body)) <*> optionalOf body)
        , (1, Case () <$> expr <*> resize 3 (listOf1 arm) <*> optionalOf body)
        , (1, While () <$> expr <*> body)
        , (1, Repeat () <$> body <*> expr)
        , (1, For () <$> (((),) <$> genIdent) <*> expr <*> expr <*> optionalOf expr <*> body)
        ]
  where
    expr = genExpr 3
    body = genStmts (n `div` 2)
    arm = CaseArm () <$> resize 3 (listOf1 caseLabel) <*> body
    caseLabel = oneof [LabelValue <$> labelValue, LabelRange <$> labelValue <*> labelValue]
    labelValue =
      oneof
        [ ELit () . (`LInt` 10) <$> choose (0, 100)
        , EUnary () Neg . ELit () . (`LInt` 10) <$> choose (0, 100)
        , EVar () <$> genIdent
        ]
    simple =
      frequency
        [ (6, Assign () <$> lvalue <*> genExpr 4)
        , (2, CallStmt () <$> genCallName <*> resize 3 (listOf (genExpr 2)))
        , (1, pure (Exit ()))
        , (1, pure (Return ()))
        , (1, pure (Empty ()))
        ]
    lvalue = oneof [LVar () <$> genVarName, LIndex () <$> genVarName <*> genExpr 2]

optionalOf :: Gen a -> Gen (Maybe a)
optionalOf g = oneof [pure Nothing, Just <$> g]

genBlock :: [VarSection] -> Gen (VarBlock ())
genBlock sections = do
  sec <- elements sections
  constant <- if sec == SecVar then arbitrary else pure False
  decls <- resize 4 (listOf (genDecl sec))
  pure (VarBlock () sec constant decls)

genDecl :: VarSection -> Gen (VarDecl ())
genDecl sec = do
  names <- resize 3 (listOf1 (((),) <$> genIdent))
  at <- case names of
    [_] | sec == SecVar -> optionalOf (((),) <$> genOperand)
    _ -> pure Nothing
  ty <- oneof [TBasic <$> elements allBasicTypes, TArray <$> genExpr 1 <*> genExpr 1 <*> elements allBasicTypes]
  ini <- optionalOf (oneof [InitExpr <$> genExpr 2, InitList () <$> resize 4 (listOf1 (genExpr 1))])
  pure (VarDecl () names at ty ini)

genOperand :: Gen OperandRef
genOperand =
  OperandRef
    <$> elements ["M", "E", "S", "A", "I", "F", "TM", "TI", "TF", "D", "KM"]
    <*> choose (0, 20000)
    <*> oneof [pure NoSub, BitOf <$> choose (0, 20), Position <$> choose (0, 300)]

genModule :: Gen (Module ())
genModule = sized $ \n -> do
  let depth = min 6 (n `div` 10 + 1)
  globals <- resize 2 (listOf (genBlock [SecVar]))
  functions <- resize 2 (listOf (genFunction depth))
  prog <- Program () <$> genIdent <*> resize 3 (listOf (genBlock allSections)) <*> genStmts depth
  pure (Module globals functions prog)
  where
    allSections = [minBound .. maxBound]
    genFunction depth =
      Function () <$> genIdent <*> elements allBasicTypes <*> resize 3 (listOf (genBlock allSections)) <*> genStmts depth
