-- | The checked, elaborated program: what the verifier produces and the
-- interpreter runs. Types are resolved, every implicit conversion is an
-- explicit 'CConv' node, every name is bound to where its value lives, and
-- every operation that can raise a runtime error carries its source line.
module Stref.Checked
  ( CModule (..)
  , ModuleKind (..)
  , CProgram (..)
  , CFunction (..)
  , FunId
  , Var (..)
  , Home (..)
  , VarInit (..)
  , InitValue (..)
  , CExpr (..)
  , ArithOp (..)
  , CmpOp (..)
  , LogicOp (..)
  , CStmt (..)
  , LTarget (..)
  , CaseRange
  , Line
  , cexprType
  , varBasicType
  ) where

import Data.IntMap.Strict (IntMap)
import Data.Text (Text)
import Stref.Operands (Operand)
import Stref.Types
import Stref.Values (Value, valueType)

-- | MT-POU-2: a procedure module (called by CHP, no parameters) or a
-- function module (called by CHF, with parameters).
data ModuleKind = ProcedureModule | FunctionModule
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | A 1-based line of the module source (decision A24).
type Line = Int

-- | Index of a function in 'cmFunctions'.
type FunId = Int

-- | Where a variable's value lives.
data Home
  = Data !Int
  -- ^ a slot of the module data area (MT-MAP-1): unmapped globals, program
  -- locals and program parameters. An array takes consecutive slots.
  | Frame !Int
  -- ^ a slot of the current function call's frame: parameters, locals and
  -- the result (slot 0), fresh on every call (MT-SCOPE-7)
  | Mapped Operand
  -- ^ the PLC operand itself (MT-MAP-2); for an array, its first element's
  -- operand (element k is the operand k - lower positions further, MT-MAP-9)
  | SignalInput !Int -- ^ INPUT1..3 (MT-SIG-2)
  | SignalOutput !Int -- ^ OUTPUT1..3 (MT-SIG-4)
  | OverflowFlag -- ^ INTERNAL_OVERFLOW (MT-OP-7)
  deriving (Eq, Show)

data Var = Var
  { varName :: Text -- ^ as declared, for messages and observation
  , varType :: Type
  , varHome :: Home
  }
  deriving (Eq, Show)

varBasicType :: Var -> BasicType
varBasicType = elementType . varType

-- | Initialisation of a variable at the start of its lifetime.
data VarInit = VarInit
  { viVar :: Var
  , viInit :: Maybe InitValue
  -- ^ 'Nothing': the type default, or for a mapped variable no write at all
  -- (MT-VAR-3, MT-MAP-4 b)
  }
  deriving (Eq, Show)

data InitValue
  = InitScalar Value
  | InitArray [Value] -- ^ exactly one value per element (MT-ARR-6, MT-ARR-7)
  deriving (Eq, Show)

data ArithOp = OpAdd | OpSub | OpMul | OpDiv | OpMod
  deriving (Eq, Ord, Show, Enum, Bounded)

data CmpOp = OpLt | OpGt | OpLe | OpGe | OpEq | OpNe
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Boolean logic on BOOL, bit by bit on BYTE, WORD, DWORD (MT-OP-12).
data LogicOp = OpAnd | OpOr | OpXor
  deriving (Eq, Ord, Show, Enum, Bounded)

-- | Typed expressions. Binary operands already have one common type: the
-- 'BasicType' stored in a node is the operands' type.
data CExpr
  = CLit Value
  | CRead Var -- ^ a scalar variable, signal or INTERNAL_OVERFLOW
  | CReadIndex !Line Var CExpr -- ^ array element; the index is a DINT expression
  | CConv BasicType BasicType CExpr -- ^ from, to: Table 4-6 (MT-CONV-5)
  | CNeg !Line BasicType CExpr -- ^ unary minus: INT, DINT, REAL (MT-OP-4)
  | CNot BasicType CExpr -- ^ BOOL complement or bitwise NOT
  | CArith !Line ArithOp BasicType CExpr CExpr
  | CCompare CmpOp BasicType CExpr CExpr
  | CLogic LogicOp BasicType CExpr CExpr
  | CCall !Line FunId BasicType [CExpr] -- ^ arguments already converted to the parameter types; result type
  | CExpt !Line BasicType CExpr CExpr -- ^ base type; exponent is USINT (MT-OP-20)
  deriving (Eq, Show)

cexprType :: CExpr -> BasicType
cexprType = \case
  CLit v -> valueType v
  CRead v -> varBasicType v
  CReadIndex _ v _ -> varBasicType v
  CConv _ t _ -> t
  CNeg _ t _ -> t
  CNot t _ -> t
  CArith _ _ t _ _ -> t
  CCompare {} -> BOOL
  CLogic _ t _ _ -> t
  CCall _ _ t _ -> t
  CExpt _ t _ _ -> t

data LTarget
  = LTVar Var
  | LTIndex !Line Var CExpr -- ^ the index is a DINT expression
  deriving (Eq, Show)

-- | An inclusive range of CASE label values.
type CaseRange = (Integer, Integer)

data CStmt
  = SAssign !Line LTarget CExpr -- ^ the value already has the target's type
  | SCall !Line FunId [CExpr] -- ^ result discarded (MT-STMT-3)
  | SIf [(Line, CExpr, [CStmt])] [CStmt] -- ^ each test with its line; ELSE (empty if none)
  | SCase !Line CExpr [([CaseRange], [CStmt])] [CStmt]
  | SWhile !Line CExpr [CStmt]
  | SRepeat [CStmt] !Line CExpr -- ^ body, line of UNTIL, test
  | SFor !Line Var CExpr CExpr CExpr [CStmt]
  -- ^ control variable, start, end, step (the literal 1 when BY is absent),
  -- all of the control variable's type (MT-STMT-16)
  | SExit !Line
  | SReturn !Line
  deriving (Eq, Show)

data CFunction = CFunction
  { cfName :: Text
  , cfLine :: !Line
  , cfResult :: BasicType
  , cfParams :: [Var] -- ^ VAR_INPUT in declaration order (MT-POU-5), homes in the frame
  , cfLocals :: [VarInit] -- ^ VAR locals, initialised on every call
  , cfFrameSize :: !Int -- ^ slot 0 holds the result
  , cfBody :: [CStmt]
  }
  deriving (Eq, Show)

data CProgram = CProgram
  { cpName :: Text
  , cpInputs :: [Var] -- ^ VAR_INPUT: the first CHF inputs (MT-PARAM-3)
  , cpInOuts :: [Var] -- ^ VAR_IN_OUT: the last CHF inputs, copied back (MT-PARAM-5)
  , cpOutputs :: [Var] -- ^ VAR_OUTPUT: the CHF outputs
  , cpBody :: [CStmt]
  }
  deriving (Eq, Show)

data CModule = CModule
  { cmFunctions :: IntMap CFunction
  , cmDataSize :: !Int -- ^ slots of the data area
  , cmInits :: [VarInit]
  -- ^ in declaration order: every unmapped global and program variable, and
  -- every mapped one with an initialiser (decision A3)
  , cmMapped :: [Var]
  -- ^ every mapped variable, in declaration order, for the operand checks
  -- that precede the first statement (MT-MAP-8, MT-MAP-10)
  , cmNamed :: [(Text, Var)]
  -- ^ observable variables by qualified name: @G@ for a global, @P.X@ for a
  -- local of program P
  , cmProgram :: CProgram
  , cmDataBytes :: !Integer -- ^ bytes of unmapped data (MT-LIM-3)
  }
  deriving (Eq, Show)
