-- | One module call (MT-EXEC-9): the pure function from the checked module,
-- the controller's state and the call's inputs to the new state, the output
-- signals and the diagnostics. STUB: owned by the interpreter work.
module Stref.Execution
  ( PlcState (..)
  , initialPlcState
  , CallInput (..)
  , defaultCallInput
  , CallResult (..)
  , runCall
  ) where

import Data.Text (Text)
import Stref.Checked
import Stref.Diagnostics
import Stref.Operands
import Stref.Policy (Policies)
import Stref.Values

-- | What outlives a module call: the operands, and (under @lifetime =
-- retained@) the data area.
data PlcState = PlcState
  { psMemory :: Memory
  , psRetained :: Maybe [Value]
  }
  deriving (Eq, Show)

initialPlcState :: PlcState
initialPlcState = PlcState emptyMemory Nothing

data CallInput = CallInput
  { ciInputs :: (Bool, Bool, Bool) -- ^ INPUT1..3 (MT-SIG-2)
  , ciChfIn :: [ChfArg] -- ^ CHF input parameters (F modules)
  , ciChfOut :: [ChfArg] -- ^ CHF output parameters (F modules)
  }
  deriving (Eq, Show)

defaultCallInput :: CallInput
defaultCallInput = CallInput (True, True, True) [] []

data CallResult = CallResult
  { crOutputs :: (Bool, Bool, Bool) -- ^ OUTPUT1..3 after the call
  , crError :: Maybe RuntimeError
  , crVars :: [(Text, Value)] -- ^ named variables at the end of the call (arrays element-wise: @P.V[3]@)
  , crSteps :: !Int -- ^ steps used of the budget
  }
  deriving (Eq, Show)

-- | Run one module call. The diagnostic band is written into the memory.
runCall :: Policies -> PlcConfig -> CModule -> CallInput -> PlcState -> (PlcState, CallResult)
runCall _ _ _ _ st = (st, CallResult (True, False, False) Nothing [] 0)
