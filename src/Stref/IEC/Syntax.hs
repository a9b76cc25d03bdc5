-- | The abstract syntax of an IEC 61131-3 compilation unit (IEC 61131-3 ed.2
-- §2 and §3; Tecomat manual §3): data type declarations, global variables,
-- functions, function blocks, programs and configurations, their variable
-- sections and the statements and expressions of Structured Text.
--
-- One tree for every IEC dialect: what a dialect accepts is decided by the
-- parser's dialect data and by the checker, not by a second tree.
module Stref.IEC.Syntax
  ( Pos (..)
  , noPos
  , Name
  , Unit (..)
  , Decl (..)
  , TypeDecl (..)
  , TypeSpec (..)
  , Init (..)
  , VarBlock (..)
  , Section (..)
  , VarDecl (..)
  , EdgeQualifier (..)
  , Location (..)
  , Attribute
  , attributeValue
  , Pou (..)
  , PouKind (..)
  , pouKindKeyword
  , Member (..)
  , Method (..)
  , Property (..)
  , Configuration (..)
  , Resource (..)
  , Task (..)
  , ProgramConfig (..)
  , Stmt (..)
  , AssignOp (..)
  , CaseLabel (..)
  , Arg (..)
  , Expr (..)
  , Literal (..)
  , UnOp (..)
  , BinOp (..)
  , exprPos
  , stmtPos
  , binOpSymbol
  , byteSized
  , incomplete
  , ConfigEntry (..)
  ) where

import Data.Text (Text)
import Stref.Syntax (Pos (..), noPos)

-- | A name as written; names compare without case (TC-LEX-15), which the
-- checker does by upper-casing.
type Name = Text

-- | A compilation unit: its declarations in source order.
newtype Unit = Unit {unitDecls :: [Decl]}
  deriving (Eq, Show)

data Decl
  = DTypes [TypeDecl] -- ^ @TYPE ... END_TYPE@ (TC-TYPE-29)
  | DGlobals VarBlock -- ^ a top-level @VAR_GLOBAL@ block (TC-VAR-13)
  | DPou Pou
  | DConfig Configuration
  | DVarConfig [ConfigEntry] -- ^ CODESYS: @VAR_CONFIG ... END_VAR@ (NX-VAR-14)
  deriving (Eq, Show)

-- | CODESYS: the address of an instance's variable declared at an incomplete
-- address (@%I*@, @%Q*@), given by its full instance path (NX-VAR-14):
-- @MainPrg.locioVar1.xLocIn AT %IX1.0 : BOOL;@
data ConfigEntry = ConfigEntry
  { cfgEntryPos :: Pos
  , cfgEntryPath :: [Name]
  , cfgEntryAt :: Location
  , cfgEntryType :: TypeSpec
  }
  deriving (Eq, Show)

data TypeDecl = TypeDecl
  { tdPos :: Pos
  , tdName :: Name
  , tdSpec :: TypeSpec
  , tdInit :: Maybe Init
  , tdAttributes :: [Attribute] -- ^ CODESYS: the attributes before the type (pack_mode, NX-PRAGMA-11)
  }
  deriving (Eq, Show)

-- | A type as written in a declaration.
data TypeSpec
  = TSName Pos Name -- ^ an elementary, derived or FB type by name
  | TSString Pos Bool (Maybe Expr) -- ^ @STRING[n]@ / @WSTRING[n]@ (True: wide)
  | TSArray Pos [(Expr, Expr)] TypeSpec -- ^ @ARRAY [a..b, c..d] OF T@
  | TSStruct Pos [VarDecl] -- ^ @STRUCT ... END_STRUCT@
  | TSUnion Pos [VarDecl] -- ^ CODESYS: @UNION ... END_UNION@ (NX-TYPE-72)
  | TSEnum Pos [(Pos, Name, Maybe Expr)] (Maybe Name) -- ^ @(a, b, c)@; CODESYS: @(a, b := 10) DINT@ (NX-TYPE-57)
  | TSSubrange Pos Name (Expr, Expr) -- ^ @INT (lo..hi)@
  | TSPointer Pos TypeSpec -- ^ CODESYS: @POINTER TO T@ (NX-TYPE-74)
  | TSExtends Pos Name TypeSpec -- ^ CODESYS: @TYPE S2 EXTENDS S1 : STRUCT ... END_STRUCT@ (NX-TYPE-55)
  deriving (Eq, Show)

-- | An initial value: an expression, an array list (with @n(v)@
-- repetitions) or a structure list.
data Init
  = IExpr Expr
  | IArray Pos [(Maybe Expr, Init)] -- ^ @[1, 2, 3(0)]@: an optional repetition count
  | IStruct Pos [(Name, Init)] -- ^ @(a := 1, b := 2)@
  deriving (Eq, Show)

data Section
  = SecVar
  | SecInput
  | SecOutput
  | SecInOut
  | SecExternal
  | SecGlobal
  | SecTemp
  | SecStat -- ^ CODESYS: VAR_STAT, one copy per POU (NX-VAR-10)
  deriving (Eq, Ord, Show, Enum, Bounded)

data VarBlock = VarBlock
  { vbPos :: Pos
  , vbSection :: Section
  , vbConstant :: Bool
  , vbRetain :: Bool
  , vbDecls :: [VarDecl]
  , vbPersistent :: Bool -- ^ CODESYS: @PERSISTENT@ (NX-VAR-20)
  , vbAttributes :: [Attribute] -- ^ CODESYS: the attributes before the block (a GVL's)
  }
  deriving (Eq, Show)

-- | CODESYS: @{attribute 'name' := 'value'}@ (NX-PRAGMA-5): the name in
-- lower case, the value ("" when none).
type Attribute = (Text, Text)

attributeValue :: Text -> [Attribute] -> Maybe Text
attributeValue = lookup

data EdgeQualifier = REdge | FEdge
  deriving (Eq, Show)

-- | A direct address: @%IX2.1@, @%QW4@, @%MD8@, Tecomat's @%X0.2@, @%Y1@,
-- @%RW10@ (TC-ADDR-1..5), kept as written and as its parts.
data Location = Location
  { locText :: Text -- ^ as written, upper case, with the @%@
  , locArea :: Char -- ^ I Q M X Y S R
  , locSize :: Char -- ^ X B W D L, or @' '@ when absent
  , locAddress :: [Integer]
  }
  deriving (Eq, Ord, Show)

-- | CODESYS: an incomplete address, @%I*@ or @%Q*@ (NX-LEX-61), which
-- VAR_CONFIG completes.
incomplete :: Location -> Bool
incomplete l = locSize l == '*'

-- | An address of a byte or more (%IB, %QW, %MD, %IL), not of a bit.
byteSized :: Location -> Bool
byteSized l = locSize l `elem` ("BWDL" :: String) && length (locAddress l) == 1

data VarDecl = VarDecl
  { vdPos :: Pos
  , vdNames :: [(Pos, Name)] -- ^ empty for an anonymous located variable
  , vdAt :: Maybe Location
  , vdType :: TypeSpec
  , vdEdge :: Maybe EdgeQualifier
  , vdInit :: Maybe Init
  , vdAttributes :: [Attribute] -- ^ CODESYS: the attributes before the declaration
  , vdArgs :: [Arg] -- ^ CODESYS: an FB instance's FB_Init inputs, @com1 : Dev(nCom := 1)@ (NX-POU-35)
  }
  deriving (Eq, Show)

data PouKind
  = KFunction
  | KFunctionBlock
  | KProgram
  | KMethod -- ^ CODESYS: a method, or a property's accessor: a frame of its own, on an instance
  | KAction -- ^ CODESYS: an action: more statements on the POU's own variables
  deriving (Eq, Show)

data Pou = Pou
  { pouPos :: Pos
  , pouKind :: PouKind
  , pouName :: Name
  , pouResult :: Maybe TypeSpec -- ^ a FUNCTION's result type
  , pouVars :: [VarBlock]
  , pouBody :: [Stmt]
  , pouEnd :: Pos -- ^ where @END_...@ stands
  , pouExtends :: Maybe (Pos, Name) -- ^ CODESYS: @FUNCTION_BLOCK B EXTENDS A@ (NX-POU-44)
  , pouMembers :: [Member] -- ^ CODESYS: methods, properties and actions, written inside the POU
  , pouAttributes :: [Attribute] -- ^ CODESYS: the attributes before the POU (no_check, NX-PRAGMA-8)
  }
  deriving (Eq, Show)

-- | The keyword that opens a POU of the kind.
pouKindKeyword :: PouKind -> Text
pouKindKeyword = \case
  KFunction -> "FUNCTION"
  KFunctionBlock -> "FUNCTION_BLOCK"
  KProgram -> "PROGRAM"
  KMethod -> "METHOD"
  KAction -> "ACTION"

-- | What CODESYS keeps as objects below a POU, in their textual form
-- (docs/nexto.md): methods (NX-POU-25), properties (NX-POU-37) and
-- actions (NX-POU-41).
data Member
  = MMethod Method
  | MProperty Property
  | MAction Pos Name [Stmt] -- ^ statements on the POU's own variables
  deriving (Eq, Show)

data Method = Method
  { mtPos :: Pos
  , mtName :: Name
  , mtResult :: Maybe TypeSpec
  , mtVars :: [VarBlock]
  , mtBody :: [Stmt]
  }
  deriving (Eq, Show)

-- | @PROPERTY name : T GET ... END_GET SET ... END_SET END_PROPERTY@: each
-- accessor is a method; inside GET the property's name is the result,
-- inside SET the value written.
data Property = Property
  { prPos :: Pos
  , prName :: Name
  , prType :: TypeSpec
  , prGet :: Maybe ([VarBlock], [Stmt])
  , prSet :: Maybe ([VarBlock], [Stmt])
  }
  deriving (Eq, Show)

data Configuration = Configuration
  { cfgPos :: Pos
  , cfgName :: Name
  , cfgGlobals :: [VarBlock]
  , cfgResources :: [Resource]
  }
  deriving (Eq, Show)

data Resource = Resource
  { resPos :: Pos
  , resName :: Name
  , resOn :: Maybe Name
  , resGlobals :: [VarBlock]
  , resTasks :: [Task]
  , resPrograms :: [ProgramConfig]
  }
  deriving (Eq, Show)

-- | @TASK name(Number := 0, INTERVAL := T#10ms, PRIORITY := 1);@
data Task = Task
  { taskPos :: Pos
  , taskName :: Name
  , taskProps :: [(Name, Expr)]
  }
  deriving (Eq, Show)

-- | @PROGRAM inst WITH task : type (params);@
data ProgramConfig = ProgramConfig
  { pcPos :: Pos
  , pcInstance :: Name
  , pcTask :: Maybe Name
  , pcType :: Name
  , pcArgs :: [Arg]
  }
  deriving (Eq, Show)

data Stmt
  = SAssign Pos Expr Expr -- ^ target (a variable expression), value
  | SCall Pos Expr [Arg] -- ^ an FB instance or a function called as a statement
  | SIf Pos [(Expr, [Stmt])] [Stmt] -- ^ IF/ELSIF arms, ELSE
  | SCase Pos Expr [([CaseLabel], [Stmt])] [Stmt]
  | SFor Pos Name Expr Expr (Maybe Expr) [Stmt] -- ^ control variable, start, end, step
  | SWhile Pos Expr [Stmt]
  | SRepeat Pos [Stmt] Expr
  | SExit Pos
  | SReturn Pos
  | SEmpty Pos
  | SContinue Pos -- ^ CODESYS: the next iteration of the innermost loop (NX-STMT-35)
  | SJump Pos Name -- ^ CODESYS: @JMP label;@ (NX-STMT-42)
  | SLabel Pos Name -- ^ CODESYS: @label:@ before the statements it marks
  | SChain Pos [(Expr, AssignOp)] Expr
  -- ^ CODESYS: @a := b := e@, @a S= e@, @a R= e@, @a S= b R= e@: the
  -- targets from left to right and the value (NX-STMT-6..9)
  deriving (Eq, Show)

-- | How a target of an assignment chain takes its value.
data AssignOp = OpAssign | OpSet | OpReset
  deriving (Eq, Show)

data CaseLabel = CaseValue Expr | CaseRange Expr Expr
  deriving (Eq, Show)

-- | An argument: positional, formal input @n := e@, or output binding
-- @n => v@ (with @NOT@ for @NOT n => v@, not used by Tecomat).
data Arg
  = ArgPositional Expr
  | ArgInput Pos Name Expr
  | ArgOutput Pos Name Expr
  deriving (Eq, Show)

data Expr
  = ELit Pos Literal
  | EVar Pos Name
  | EField Pos Expr Name -- ^ @r.f@, @inst.Q@
  | EIndex Pos Expr [Expr] -- ^ @a[i, j]@
  | ELocated Pos Location -- ^ a direct address used in an expression
  | EUn Pos UnOp Expr
  | EBin Pos BinOp Expr Expr
  | ECall Pos Name [Arg] -- ^ a function call
  | EEnum Pos Name Name -- ^ @TYPE#value@
  | EDeref Pos Expr -- ^ CODESYS: @p^@ (NX-TYPE-75), @THIS^@, @SUPER^@
  | EInvoke Pos Expr [Arg] -- ^ a call of what an expression names: @inst.m(..)@, @p^.m()@, @SUPER^()@
  | EGlobalScope Pos Name -- ^ CODESYS: @.name@, the global (NX-OP-88, NX-VAR-34)
  | EBit Pos Expr Integer -- ^ CODESYS: @x.3@, a bit of an integer (NX-OP-92)
  | EThis Pos -- ^ CODESYS: @THIS@, a pointer to the running FB instance (NX-POU-28)
  | ESuper Pos -- ^ CODESYS: @SUPER@, that instance as its base FB (NX-POU-46)
  deriving (Eq, Show)

data Literal
  = LInt Integer -- ^ an untyped integer (TC-LEX-20..22)
  | LReal Rational Text -- ^ an untyped real, exactly, and as written
  | LBool Bool
  | LTyped Name Literal -- ^ @INT#5@, @REAL#1.0@, @BOOL#1@ (TC-LEX-24)
  | LBits Integer -- ^ a based integer after a type, @DINT#16#FFFFFFFF@ (a bit pattern under CODESYS: NX-LEX-33)
  | LString Text -- ^ after escapes (TC-LEX-28..38)
  | LWString Text
  | LTime Integer -- ^ a duration, exactly, in nanoseconds (TC-LEX-41, TC-LEX-44)
  | LDate Integer -- ^ nanoseconds from 1970-01-01 to the date's midnight (TC-LEX-42)
  | LTod Integer -- ^ nanoseconds since midnight
  | LDT Integer -- ^ nanoseconds since 1970-01-01
  deriving (Eq, Show)

data UnOp = UNeg | UNot | UPlus
  deriving (Eq, Show)

data BinOp
  = BPow
  | BMul
  | BDiv
  | BMod
  | BAdd
  | BSub
  | BLt
  | BGt
  | BLe
  | BGe
  | BEq
  | BNe
  | BAnd
  | BXor
  | BOr
  deriving (Eq, Show, Enum, Bounded)

binOpSymbol :: BinOp -> Text
binOpSymbol = \case
  BPow -> "**"
  BMul -> "*"
  BDiv -> "/"
  BMod -> "MOD"
  BAdd -> "+"
  BSub -> "-"
  BLt -> "<"
  BGt -> ">"
  BLe -> "<="
  BGe -> ">="
  BEq -> "="
  BNe -> "<>"
  BAnd -> "AND"
  BXor -> "XOR"
  BOr -> "OR"

exprPos :: Expr -> Pos
exprPos = \case
  ELit p _ -> p
  EVar p _ -> p
  EField p _ _ -> p
  EIndex p _ _ -> p
  ELocated p _ -> p
  EUn p _ _ -> p
  EBin p _ _ _ -> p
  ECall p _ _ -> p
  EEnum p _ _ -> p
  EDeref p _ -> p
  EInvoke p _ _ -> p
  EGlobalScope p _ -> p
  EThis p -> p
  EBit p _ _ -> p
  ESuper p -> p

stmtPos :: Stmt -> Pos
stmtPos = \case
  SAssign p _ _ -> p
  SCall p _ _ -> p
  SIf p _ _ -> p
  SCase p _ _ _ -> p
  SFor p _ _ _ _ _ -> p
  SWhile p _ _ -> p
  SRepeat p _ _ -> p
  SExit p -> p
  SReturn p -> p
  SEmpty p -> p
  SContinue p -> p
  SJump p _ -> p
  SLabel p _ -> p
  SChain p _ _ -> p
