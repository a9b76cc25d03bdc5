-- | A checked IEC program: names resolved, every expression typed, untyped
-- literals given the type of their context, initial values computed. The
-- evaluator ("Stref.IEC.Eval") runs this, never the raw syntax.
module Stref.IEC.Checked
  ( Program (..)
  , PouDef (..)
  , Body (..)
  , VarInfo (..)
  , Retention (..)
  , CExpr (..)
  , CNode (..)
  , CRef (..)
  , Dispatch (..)
  , CStmt (..)
  , FBCall (..)
  , StandardFB
  , FBState
  , lookupPou
  , declaredNames
  , findMethod
  , varByKey
  , key
  ) where

import Data.Map.Strict (Map)
import qualified Data.Map.Strict as M
import Data.Text (Text)
import Stref.IEC.Syntax (AssignOp, BinOp, EdgeQualifier, Location, Pos, PouKind, Section, UnOp)
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy (Policies, TimeRange)

-- | Names compare without case (TC-LEX-15): every map is keyed by the
-- upper-case name.
key :: Text -> Text
key = upperName

data Program = Program
  { prPous :: Map Text PouDef -- ^ user and standard POUs by key
  , prGlobals :: [VarInfo] -- ^ in declaration order
  , prRoots :: [(Text, Text)] -- ^ every program's instance (those the tasks run, and those only called): instance name, type key
  , prInstances :: [(Text, Text)] -- ^ program instances run each cycle, in order: instance name, program type key
  , prTaskInterval :: Maybe Integer -- ^ the interval of the configuration's task, milliseconds, if it states one
  , prPeriods :: Map Text Integer -- ^ the program instances of periodic tasks, by key: their task's INTERVAL in milliseconds (TC-CFG-9, NX-TASK-1)
  , prGvls :: Map Text (Map Text Text) -- ^ CODESYS: each named global list's variables, by key, and where each is stored (NX-VAR-35)
  , prGlobalInits :: [(Text, Type, CExpr)] -- ^ CODESYS: the globals' initial values that are not constants, in the order the lists initialise (NX-VAR-26, NX-VAR-27)
  , prGlobalInitArgs :: Map Text [(Text, CExpr)] -- ^ CODESYS: the FB_Init inputs of global instances (NX-POU-35)
  , prChecks :: [Text] -- ^ the implicit check functions the program declares, by key (NX-ERR-1)
  , prPackModes :: Map Text Integer -- ^ CODESYS: the pack_mode of each structure type that states one, by key (NX-PRAGMA-11)
  , prVarConfig :: [(Char, [Step], Location, Type)] -- ^ CODESYS: each instance variable VAR_CONFIG places, its class (I, Q), path, address and type (NX-VAR-14)
  , prTimeRange :: TimeRange -- ^ how a TIME is read from the bytes of a direct address (policy time-range)
  }

-- | A declared variable.
data VarInfo = VarInfo
  { viName :: Text -- ^ as declared
  , viKey :: Text
  , viSection :: Section
  , viType :: Type
  , viInit :: Value -- ^ the initial value (TC-TYPE-21..23, TC-VAR-36)
  , viConstant :: Bool
  , viAt :: Maybe Location
  , viEdge :: Maybe EdgeQualifier
  , viPos :: Pos
  , viRetention :: Retention -- ^ what a reset of the controller does to it (NX-VAR-21, NX-VAR-22)
  }

-- | CODESYS: a variable's life over the controller's resets (Table 4-4):
-- VAR RETAIN, VAR PERSISTENT, the attribute no_init (NX-PRAGMA-9).
data Retention = Volatile | RetainOverWarm | Persistent | NoInit
  deriving (Eq, Show)

varByKey :: PouDef -> Text -> Maybe VarInfo
varByKey p k = M.lookup k (pdVarMap p)

-- | The state of a standard FB instance: its variables by key.
type FBState = Map Text Value

-- | A standard FB's meaning: the policies, the clock (milliseconds) and the
-- instance's variables after the inputs were written, to its variables
-- after the call.
type StandardFB = Policies -> Integer -> FBState -> FBState

data Body = Statements [CStmt] | Native StandardFB

data PouDef = PouDef
  { pdKind :: PouKind
  , pdName :: Text
  , pdVars :: [VarInfo] -- ^ in declaration order
  , pdVarMap :: Map Text VarInfo
  , pdResult :: Maybe Type
  , pdBody :: Body
  , pdEndPos :: Pos
  , pdBase :: Maybe Text -- ^ the FB it extends, by key (NX-POU-44)
  , pdInits :: [(Text, Type, CExpr)] -- ^ CODESYS: initial values that are not constants, in declaration order (NX-VAR-24)
  , pdInitArgs :: Map Text [(Text, CExpr)] -- ^ CODESYS: the FB_Init inputs given at an instance's declaration, by instance key (NX-POU-35)
  , pdChecked :: Bool -- ^ do the implicit check functions apply in its body? (not in themselves, nor under no_check: NX-ERR-3, NX-ERR-4)
  , pdMethods :: Map Text PouDef -- ^ its own methods, property accessors and actions, by key
  }

lookupPou :: Program -> Text -> Maybe PouDef
lookupPou p n = M.lookup (key n) (prPous p)

-- | Every variable's name as declared, by key (where two POUs spell one
-- key differently, one of the spellings): for messages and the trace.
declaredNames :: Program -> Map Text Text
declaredNames prog = M.fromList [(viKey v, viName v) | v <- prGlobals prog ++ concatMap pdVars (M.elems (prPous prog))]

-- | A method (accessor, action) of a POU type, its own or inherited, with
-- the type that declares it.
findMethod :: Program -> Text -> Text -> Maybe PouDef
findMethod prog t m = go (16 :: Int) t
  where
    go 0 _ = Nothing
    go n k = do
      d <- lookupPou prog k
      case M.lookup (key m) (pdMethods d) of
        Just md -> Just md
        Nothing -> pdBase d >>= go (n - 1)

-- | A typed expression.
data CExpr = CExpr {cePos :: Pos, ceType :: Type, ceNode :: CNode}

data CNode
  = CConst Value
  | CRead CRef
  | CUnary UnOp CExpr
  | CBinary BinOp CExpr CExpr
  | CConvert Type CExpr -- ^ a conversion to the node's type from the operand's
  | CStandard Text [CExpr] -- ^ a standard function by key, its arguments in order
  | CCall Text [(Text, CExpr)] [(Text, CRef)] [(Text, CRef, Type)]
  -- ^ a user function: inputs by parameter key, in-outs by reference, and
  -- (CODESYS, NX-POU-13) outputs bound with @=>@
  | CAddressOf CRef -- ^ CODESYS: @ADR(x)@ (NX-TYPE-75, NX-OP-68)
  | CMethod Dispatch CRef [(Text, CExpr)] [(Text, CRef)] [(Text, CRef, Type)]
  -- ^ a method, accessor or action of an instance: its inputs, in-outs and
  -- @=>@ outputs; the value is the method's result

-- | Which method a call runs: the one the instance's own type has (or
-- inherits), found when the call runs (NX-POU-31); or the one of a named FB
-- type (@SUPER^.m()@, NX-POU-46).
data Dispatch = Virtual Text | Static Text Text

-- | A variable as the program names it.
data CRef
  = CLocal Text -- ^ a variable of the running POU (instance or frame)
  | CGlobal Text
  | CField CRef Text -- ^ a structure's field or an FB instance's variable
  | CIndex CRef [CExpr] -- ^ an array element
  | CLocated Location Type -- ^ a direct address read as a type
  | CProgram Text -- ^ CODESYS: a program's instance, by key (NX-POU-3)
  | CBit CRef Int -- ^ CODESYS: a bit of an integer variable (NX-OP-92, NX-OP-93)
  | CThis -- ^ the instance a function block's body, method or action runs on (NX-POU-28)
  | CDeref CExpr Type -- ^ CODESYS: what a pointer points at, of the pointer's base type (NX-TYPE-75)
  | CCharAt Bool CRef CExpr -- ^ CODESYS: @s[i]@ (True: a WSTRING), the code of a STRING's (WSTRING's) character i, from 0 (NX-TYPE-77)
  | CInstance Text -- ^ a variable of that instance, named inside one of its methods (NX-POU-27)

data FBCall = FBCall
  { fcInstance :: CRef
  , fcType :: Text -- ^ the FB's key
  , fcInputs :: [(Text, CExpr)]
  , fcInOuts :: [(Text, CRef)]
  , fcOutputs :: [(Text, CRef, Type)] -- ^ @out => v@ and v's type: copied after the body (TC-POU-36)
  }

data CStmt
  = CAssign Pos CRef Type CExpr -- ^ the target's declared type decides truncation and range checks
  | CCallFB Pos FBCall
  | CEval Pos CExpr -- ^ a function called as a statement, its result dropped
  | CIf Pos [(CExpr, [CStmt])] [CStmt]
  | CCase Pos CExpr [([(Integer, Integer)], [CStmt])] [CStmt] -- ^ labels as ranges of ordinals
  | CFor Pos CRef Type CExpr CExpr (Maybe CExpr) [CStmt] -- ^ the control variable and its declared type
  | CWhile Pos CExpr [CStmt]
  | CRepeat Pos [CStmt] CExpr
  | CExit Pos
  | CReturn Pos
  | CContinue Pos
  | CJump Pos Text -- ^ to a label (upper case) of this or an enclosing block
  | CLabel Pos Text
  | CChain Pos CExpr [(AssignOp, CRef, Type, Maybe Type)]
  -- ^ the value, then the targets from left to right: how each takes the
  -- value, where it lies, its type, and the type to convert from when the
  -- value reaching it has another
