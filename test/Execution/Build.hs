-- | Small builders for hand-made checked programs, so that the interpreter
-- can be tested without the parser and the checker.
module Execution.Build
  ( -- * Literals
    int
  , dint
  , usint
  , bool
  , word
    -- * Variables
  , dataVar
  , frameVar
  , mappedVar
  , op
  , out1
  , out2
  , in2
  , overflowFlag
    -- * Expressions and statements
  , rd
  , rdAt
  , add
  , sub
  , divide
  , cmp
  , andE
  , orE
  , assign
  , assignAt
    -- * Modules
  , ModuleSpec (..)
  , spec0
  , build
  , function
    -- * Running
  , runOnce
  , runWith
  , runN
  , varValue
  , bandOf
  , operandValue
  ) where

import qualified Data.IntMap.Strict as IM
import Data.Text (Text)
import Stref.Checked
import Stref.Execution
import Stref.Operands
import Stref.Policy
import Stref.Types
import Stref.Values

int, dint, usint, word :: Integer -> CExpr
int = CLit . VInt . fromInteger
dint = CLit . VDInt . fromInteger
usint = CLit . VUSInt . fromInteger
word = CLit . VWord . fromInteger

bool :: Bool -> CExpr
bool = CLit . VBool

dataVar :: Text -> Type -> Int -> Var
dataVar n t i = Var n t (Data i)

frameVar :: Text -> Type -> Int -> Var
frameVar n t i = Var n t (Frame i)

mappedVar :: Text -> Type -> Text -> Var
mappedVar n t o = Var n t (Mapped (op o))

-- | An operand from its text; the tests only use valid spellings.
op :: Text -> Operand
op t = either (const (OpSimple KM 0)) id (parseOperand t)

out1, out2, in2, overflowFlag :: Var
out1 = Var "OUTPUT1" (Basic BOOL) (SignalOutput 1)
out2 = Var "OUTPUT2" (Basic BOOL) (SignalOutput 2)
in2 = Var "INPUT2" (Basic BOOL) (SignalInput 2)
overflowFlag = Var "INTERNAL_OVERFLOW" (Basic BOOL) OverflowFlag

rd :: Var -> CExpr
rd = CRead

rdAt :: Line -> Var -> CExpr -> CExpr
rdAt = CReadIndex

add, sub :: Line -> CExpr -> CExpr -> CExpr
add l a b = CArith l OpAdd (cexprType a) a b
sub l a b = CArith l OpSub (cexprType a) a b

divide :: Line -> CExpr -> CExpr -> CExpr
divide l a b = CArith l OpDiv (cexprType a) a b

cmp :: CmpOp -> CExpr -> CExpr -> CExpr
cmp o a b = CCompare o (cexprType a) a b

andE, orE :: CExpr -> CExpr -> CExpr
andE = CLogic OpAnd BOOL
orE = CLogic OpOr BOOL

assign :: Line -> Var -> CExpr -> CStmt
assign l v = SAssign l (LTVar v)

assignAt :: Line -> Var -> CExpr -> CExpr -> CStmt
assignAt l v ix = SAssign l (LTIndex l v ix)

-- | What a test module is made of. Unmapped data variables are initialised
-- to their default unless 'msInits' says otherwise; every variable is
-- observable as @P.<name>@.
data ModuleSpec = ModuleSpec
  { msVars :: [Var] -- ^ data-area and mapped variables, in declaration order
  , msInits :: [(Text, InitValue)] -- ^ initialisers by name
  , msFunctions :: [CFunction]
  , msInputs :: [Var]
  , msInOuts :: [Var]
  , msOutputs :: [Var]
  , msBody :: [CStmt]
  }

spec0 :: ModuleSpec
spec0 = ModuleSpec [] [] [] [] [] [] []

build :: ModuleSpec -> CModule
build s =
  CModule
    { cmFunctions = IM.fromList (zip [0 ..] (msFunctions s))
    , cmDataSize = 64
    , cmInits =
        [ VarInit v (lookup (varName v) (msInits s))
        | v <- msVars s
        , case varHome v of
            Mapped _ -> varName v `elem` map fst (msInits s)
            _ -> True
        ]
    , cmMapped = [v | v <- msVars s, isMapped v]
    , cmNamed = [("P." <> varName v, v) | v <- msVars s ++ msInputs s ++ msInOuts s ++ msOutputs s]
    , cmProgram = CProgram "P" (msInputs s) (msInOuts s) (msOutputs s) (msBody s)
    , cmDataBytes = 0
    }
  where
    isMapped v = case varHome v of
      Mapped _ -> True
      _ -> False

-- | A function with the given parameters (frame slots 1..) and locals.
function :: Text -> BasicType -> [Var] -> [VarInit] -> [CStmt] -> CFunction
function n t params locals body =
  CFunction n 1 t params locals (1 + length params + length locals + 16) body

runWith :: Policies -> PlcConfig -> CallInput -> PlcState -> CModule -> (PlcState, CallResult)
runWith p cfg ci st cm = runCall p cfg cm ci st

runOnce :: Policies -> CModule -> (PlcState, CallResult)
runOnce p = runWith p defaultPlcConfig defaultCallInput initialPlcState

-- | N calls with the default inputs, from the given memory.
runN :: Policies -> Int -> PlcState -> CModule -> (PlcState, [CallResult])
runN p n st cm = runCalls p defaultPlcConfig cm (replicate n defaultCallInput) st

varValue :: Text -> CallResult -> Maybe Value
varValue n r = lookup n (crVars r)

-- | The diagnostic band (%M1990..%M1994 in the default layout) as INTs.
bandOf :: PlcState -> [Integer]
bandOf st =
  [ maybe 0 id (valueToInteger (readOperand (psMemory st) o INT))
  | o <- diagnosticBand defaultPlcConfig
  ]

operandValue :: PlcState -> Text -> BasicType -> Value
operandValue st o = readOperand (psMemory st) (op o)
