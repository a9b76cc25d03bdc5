-- | The abstract syntax of a MasterTool XE ST module (catalogue §§ 1, 5-8), as
-- the parser produces it and the printer consumes it.
--
-- Every node carries an annotation @a@: the parser fills it with the source
-- position ('Pos'); @() <$ m@ forgets positions, which is how two trees are
-- compared for the print/parse round trip.
module Stref.Syntax
  ( Pos (..)
  , noPos
  , Ident (..)
  , Module (..)
  , VarBlock (..)
  , VarSection (..)
  , VarDecl (..)
  , TypeSpec (..)
  , Initializer (..)
  , OperandRef (..)
  , OperandSub (..)
  , Function (..)
  , Program (..)
  , Stmt (..)
  , CaseArm (..)
  , CaseLabel (..)
  , LValue (..)
  , Expr (..)
  , Literal (..)
  , UnOp (..)
  , BinOp (..)
  , exprAnn
  , stmtAnn
  , binOpSymbol
  , unOpSymbol
  ) where

import Data.Text (Text)
import GHC.Generics (Generic)
import Stref.Types (BasicType)

-- | A source position: 1-based line and column.
data Pos = Pos {posLine :: !Int, posCol :: !Int}
  deriving (Eq, Ord, Show, Generic)

-- | The position of generated nodes.
noPos :: Pos
noPos = Pos 0 0

-- | An identifier as written. Comparison of names (case, significant length)
-- is the checker's business: it depends on the @identifier-length@ policy.
newtype Ident = Ident {identText :: Text}
  deriving (Eq, Ord, Show, Generic)

-- | MT-POU-1: global variable blocks, then functions, then the one PROGRAM.
data Module a = Module
  { modGlobals :: [VarBlock a]
  , modFunctions :: [Function a]
  , modProgram :: Program a
  }
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | @VAR [CONSTANT] ... END_VAR@ and the parameter sections (MT-VAR-2, MT-VAR-5,
-- MT-POU-3, MT-POU-12).
data VarBlock a = VarBlock
  { vbAnn :: a
  , vbSection :: VarSection
  , vbConstant :: Bool
  , vbDecls :: [VarDecl a]
  }
  deriving (Eq, Show, Functor, Foldable, Traversable)

data VarSection = SecVar | SecInput | SecInOut | SecOutput
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | @A, B : INT := 3;@ or @X AT %M0010 : INT;@ (MT-VAR-2, MT-VAR-4, MT-MAP-4).
-- The parser allows @AT@ only with a single name.
data VarDecl a = VarDecl
  { vdAnn :: a
  , vdNames :: [(a, Ident)]
  , vdAt :: Maybe (a, OperandRef)
  , vdType :: TypeSpec a
  , vdInit :: Maybe (Initializer a)
  }
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | A basic type, or a one-dimensional array (MT-TYPE-4, MT-ARR-1). Bounds are
-- expressions so that the checker, not the parser, decides what a bound may be.
data TypeSpec a
  = TBasic BasicType
  | TArray (Expr a) (Expr a) BasicType
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | @:= expr@ or @:= [e1, e2, ...]@ (MT-ARR-6).
data Initializer a
  = InitExpr (Expr a)
  | InitList a [Expr a]
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | A PLC operand address as written after @AT@ (MT-MAP-5..7): the letters
-- after @%@, the address, and a bit or a table position. Whether the operand
-- exists in the language (%D does not) is checked later ("Operand ... is not
-- valid", MT-VERR-39), so the parser keeps what it read.
data OperandRef = OperandRef
  { orLetters :: Text -- ^ upper-cased: @M@, @TM@, @A@, @D@, ...
  , orAddress :: Integer
  , orSub :: OperandSub
  }
  deriving (Eq, Ord, Show, Generic)

data OperandSub
  = NoSub
  | BitOf Integer -- ^ @%M0006.6@
  | Position Integer -- ^ @%TM010[15]@
  deriving (Eq, Ord, Show, Generic)

-- | @FUNCTION name : type ... END_FUNCTION@ (MT-POU-3).
data Function a = Function
  { fnAnn :: a
  , fnName :: Ident
  , fnResult :: BasicType
  , fnBlocks :: [VarBlock a]
  , fnBody :: [Stmt a]
  }
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | @PROGRAM name ... END_PROGRAM@ (MT-POU-12).
data Program a = Program
  { prAnn :: a
  , prName :: Ident
  , prBlocks :: [VarBlock a]
  , prBody :: [Stmt a]
  }
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | Statements (MT-STMT-1).
data Stmt a
  = Assign a (LValue a) (Expr a) -- ^ MT-STMT-2
  | CallStmt a Ident [Expr a] -- ^ MT-STMT-3
  | If a [(Expr a, [Stmt a])] (Maybe [Stmt a]) -- ^ MT-STMT-6: IF and ELSIFs, ELSE
  | Case a (Expr a) [CaseArm a] (Maybe [Stmt a]) -- ^ MT-STMT-8
  | While a (Expr a) [Stmt a] -- ^ MT-STMT-13
  | Repeat a [Stmt a] (Expr a) -- ^ MT-STMT-14
  | For a (a, Ident) (Expr a) (Expr a) (Maybe (Expr a)) [Stmt a] -- ^ MT-STMT-15
  | Exit a -- ^ MT-STMT-12
  | Return a -- ^ MT-STMT-4, MT-STMT-5
  | Empty a -- ^ MT-STMT-23: a lone @;@
  deriving (Eq, Show, Functor, Foldable, Traversable)

data CaseArm a = CaseArm {caAnn :: a, caLabels :: [CaseLabel a], caBody :: [Stmt a]}
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | A CASE label: a value or a sub-range @lo..hi@ (MT-STMT-8). Labels are
-- expressions (a literal, a signed literal, or a CONSTANT's name).
data CaseLabel a
  = LabelValue (Expr a)
  | LabelRange (Expr a) (Expr a)
  deriving (Eq, Show, Functor, Foldable, Traversable)

data LValue a
  = LVar a Ident
  | LIndex a Ident (Expr a)
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | Expressions (MT-OP-2). Parentheses are not kept: the printer puts back
-- those the precedence of Table 4-14 needs (MT-OP-16, MT-OP-17).
data Expr a
  = ELit a Literal
  | EVar a Ident
  | EIndex a Ident (Expr a)
  | ECall a Ident [Expr a] -- ^ user functions, EXPT, conversions
  | EUnary a UnOp (Expr a)
  | EBinary a BinOp (Expr a) (Expr a)
  deriving (Eq, Show, Functor, Foldable, Traversable)

-- | Literals (MT-LEX-9..16). A sign is not part of a literal: @-1_532@ is
-- unary minus applied to 1532, and the checker folds it back for the range
-- checks of Table 4-15 (MT-LEX-19).
data Literal
  = LInt Integer Int -- ^ value and the base it was written in (2, 8, 10, 16)
  | LReal Rational -- ^ the exact decimal value; rounded to binary32 when typed
  | LBool Bool
  deriving (Eq, Show, Generic)

data UnOp = Neg | Not
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Binary operators; @&@ is read as 'And' (MT-OP-14).
data BinOp
  = Add | Sub | Mul | Div | Mod
  | Lt | Gt | Le | Ge
  | Eq | Ne
  | And | Xor | Or
  deriving (Eq, Ord, Show, Enum, Bounded)

exprAnn :: Expr a -> a
exprAnn = \case
  ELit a _ -> a
  EVar a _ -> a
  EIndex a _ _ -> a
  ECall a _ _ -> a
  EUnary a _ _ -> a
  EBinary a _ _ _ -> a

stmtAnn :: Stmt a -> a
stmtAnn = \case
  Assign a _ _ -> a
  CallStmt a _ _ -> a
  If a _ _ -> a
  Case a _ _ _ -> a
  While a _ _ -> a
  Repeat a _ _ -> a
  For a _ _ _ _ _ -> a
  Exit a -> a
  Return a -> a
  Empty a -> a

binOpSymbol :: BinOp -> Text
binOpSymbol = \case
  Add -> "+"
  Sub -> "-"
  Mul -> "*"
  Div -> "/"
  Mod -> "MOD"
  Lt -> "<"
  Gt -> ">"
  Le -> "<="
  Ge -> ">="
  Eq -> "="
  Ne -> "<>"
  And -> "AND"
  Xor -> "XOR"
  Or -> "OR"

unOpSymbol :: UnOp -> Text
unOpSymbol = \case
  Neg -> "-"
  Not -> "NOT"
