-- | Runtime errors and the diagnostic operands (catalogue §11, Tables 5-2 and
-- 5-3).
module Stref.Diagnostics
  ( RuntimeError (..)
  , runtimeError
  , ErrorCode
  , errOperandNotDeclared
  , errTableNotDeclared
  , errTablePositionNotDeclared
  , errInputParameter
  , errOutputParameter
  , errInputOperandNotDeclared
  , errOutputOperandNotDeclared
  , errConstantValue
  , errInputCount
  , errOutputCount
  , errInputArrayTooShort
  , errOutputArrayTooShort
  , errIndex
  , errDivisionByZero
  , errExecutionTime
  , errCallDepth
  , trapOverflow
  , trapDivisionByZero
  , trapIndex
  , errModZero
  , errOperandTypes
  , describeErrorCode
  , noErrorBand
  , errorBand
  , errorRule
  ) where

import Data.Text (Text)
import qualified Data.Text as T

type ErrorCode = Int

-- | A runtime error: its code (Table 5-3), the line where it occurred
-- (MT-DIAG-2; decision A2 for errors before the first line) and the three
-- complements (0 where "not used", decision A25).
data RuntimeError = RuntimeError
  { reCode :: !ErrorCode
  , reLine :: !Int
  , reComp :: !(Int, Int, Int)
  }
  deriving (Eq, Show)

runtimeError :: ErrorCode -> Int -> RuntimeError
runtimeError c l = RuntimeError c l (0, 0, 0)

errOperandNotDeclared, errTableNotDeclared, errTablePositionNotDeclared :: ErrorCode
errOperandNotDeclared = 2000 -- MT-ERR-2000
errTableNotDeclared = 2001 -- MT-ERR-2001
errTablePositionNotDeclared = 2002 -- MT-ERR-2002

errInputParameter, errOutputParameter, errInputOperandNotDeclared, errOutputOperandNotDeclared :: ErrorCode
errInputParameter = 2003 -- MT-ERR-2003
errOutputParameter = 2004 -- MT-ERR-2004
errInputOperandNotDeclared = 2005 -- MT-ERR-2005
errOutputOperandNotDeclared = 2006 -- MT-ERR-2006

errConstantValue, errInputCount, errOutputCount, errInputArrayTooShort, errOutputArrayTooShort :: ErrorCode
errConstantValue = 2008 -- MT-ERR-2008
errInputCount = 2009 -- MT-ERR-2009
errOutputCount = 2010 -- MT-ERR-2010
errInputArrayTooShort = 2011 -- MT-ERR-2011
errOutputArrayTooShort = 2012 -- MT-ERR-2012

errIndex, errDivisionByZero, errExecutionTime, errCallDepth :: ErrorCode
errIndex = 2015 -- MT-ERR-2015
errDivisionByZero = 2020 -- MT-ERR-2020
errExecutionTime = 2030 -- MT-ERR-2030
errCallDepth = 2050 -- MT-ERR-2050

-- | Codes of the @trap@ alternatives of the policies, which MasterTool never
-- uses (docs/policies.md): a trap stops the call like a runtime error.
trapOverflow, trapDivisionByZero, trapIndex, errModZero :: ErrorCode
trapOverflow = 9001
trapDivisionByZero = 9002
trapIndex = 9003
errModZero = 9004 -- the @error@ alternative of @mod-zero@

-- | An operator applied to values whose types the checker should have
-- rejected (e.g. MOD on REAL, unary minus on USINT): never produced for a
-- checked program; it reports a defect of stref itself, not of the program.
errOperandTypes :: ErrorCode
errOperandTypes = 9005

describeErrorCode :: ErrorCode -> Text
describeErrorCode = \case
  2000 -> "access to an operand the configuration does not declare"
  2001 -> "table operand not declared"
  2002 -> "table position not declared"
  2003 -> "incorrect input parameter"
  2004 -> "incorrect output parameter"
  2005 -> "the operand of an input parameter is not declared"
  2006 -> "the operand of an output parameter is not declared"
  2008 -> "invalid value for a constant operand"
  2009 -> "incorrect number of input parameters"
  2010 -> "incorrect number of output parameters"
  2011 -> "array input parameter with too few positions"
  2012 -> "array output parameter with too few positions"
  2015 -> "array index out of range"
  2020 -> "division by zero"
  2030 -> "execution time exceeded (step budget)"
  2050 -> "more than 16 nested function calls"
  9001 -> "integer overflow (trap policy)"
  9002 -> "division by zero (trap policy)"
  9003 -> "array index out of range (trap policy)"
  9004 -> "MOD by zero (error policy)"
  9999 -> "internal: the checked program is inconsistent (a checker bug)"
  9005 -> "internal error: operator applied to operands of the wrong types"
  _ -> "unknown error code"

-- | MT-DIAG-4: the band after a call without error.
noErrorBand :: [Int]
noErrorBand = [-32768, 0, 0, 0, 0]

-- | MT-DIAG-2: line, code, complements 1-3.
errorBand :: RuntimeError -> [Int]
errorBand (RuntimeError c l (a, b, d)) = [l, c, a, b, d]

-- | The catalogue rule that raises a runtime error (a trace cites it): the
-- code's row of Table 5-3, or for the @trap@ and @error@ alternatives of
-- the policies the rule they replace; none for stref's own errors.
errorRule :: ErrorCode -> Maybe Text
errorRule c
  | c >= 2000 && c < 3000 = Just ("MT-ERR-" <> T.pack (show c))
  | c == trapOverflow = Just "MT-OP-6"
  | c == trapDivisionByZero = Just "MT-OP-9"
  | c == trapIndex = Just "MT-ARR-8"
  | c == errModZero = Just "MT-OP-8"
  | otherwise = Nothing
