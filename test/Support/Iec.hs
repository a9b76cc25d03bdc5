-- | Running IEC programs in the tests: a PROGRAM MAIN body over cycles of
-- 10 ms, the reject kind (or message) of a unit, the runtime error of a run.
module Support.Iec
  ( runMain
  , runUnit
  , runCalls
  , rejectKind
  , rejectMessage
  , errorOf
  ) where

import Data.Text (Text)
import Stref.IEC.Check (ProgramChoice (..))
import Stref.IEC.Engine
import Stref.IEC.Eval (Stop (..), readVariablePath)
import Stref.IEC.Syntax (Pos (..))
import Stref.IEC.Values
import Stref.Policy (Policies)
import Stref.Verification (VerificationError (..))

-- | Run a program body (with its VAR blocks) as PROGRAM MAIN for n cycles of
-- 10 ms and read one variable of MAIN.
runMain :: Policies -> Text -> Int -> Text -> Either Text Value
runMain pol body n var = runUnit pol ("PROGRAM MAIN\n" <> body <> "\nEND_PROGRAM\n") n ("MAIN." <> var)

-- | Run a whole unit (its only PROGRAM, or its configuration) for n cycles
-- and read a variable path.
runUnit :: Policies -> Text -> Int -> Text -> Either Text Value
runUnit pol src n path = case runProgram pol "t.st" src ProgramsOfConfiguration 10 [] (replicate n (Scan [])) of
  Left e -> Left ("rejected: " <> veKind e <> ": " <> veMessage e)
  Right (Left e) -> Left e
  Right (Right r) -> case parseVarPath path of
    Right steps -> maybe (Left "no such variable") (Right . fst) (readVariablePath (rrProgram r) (rrMachine r) steps)
    Left e -> Left e

-- | Run a whole unit over scan cycles and resets, and read a variable path.
runCalls :: Policies -> Text -> [Call] -> Text -> Either Text Value
runCalls pol src calls path = case runProgram pol "t.st" src ProgramsOfConfiguration 10 [] calls of
  Left e -> Left ("rejected: " <> veKind e <> ": " <> veMessage e)
  Right (Left e) -> Left e
  Right (Right r) -> case parseVarPath path of
    Right steps -> maybe (Left "no such variable") (Right . fst) (readVariablePath (rrProgram r) (rrMachine r) steps)
    Left e -> Left e

rejectKind :: Policies -> Text -> Maybe (Text, Int)
rejectKind pol src = case runProgram pol "t.st" src ProgramsOfConfiguration 10 [] [Scan []] of
  Left (VerificationError k (Pos l _) _) -> Just (k, l)
  _ -> Nothing

-- | The message of the error that rejects a unit.
rejectMessage :: Policies -> Text -> Maybe Text
rejectMessage pol src = case runProgram pol "t.st" src ProgramsOfConfiguration 10 [] [Scan []] of
  Left (VerificationError _ _ m) -> Just m
  _ -> Nothing

errorOf :: Policies -> Text -> Int -> Maybe (Int, Text)
errorOf pol body n = case runProgram pol "t.st" ("PROGRAM MAIN\n" <> body <> "\nEND_PROGRAM\n") ProgramsOfConfiguration 10 [] (replicate n (Scan [])) of
  Right (Right r) -> (\(k, StopFault _ f) -> (k, faultKind f)) <$> rrError r
  _ -> Nothing
