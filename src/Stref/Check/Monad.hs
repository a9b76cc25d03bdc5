-- | The checker's monad: the environment of names (catalogue §9), the
-- accumulated verification errors, and name resolution under the
-- @name-resolution@ policy.
module Stref.Check.Monad
  ( Check
  , runCheck
  , Env (..)
  , St (..)
  , Pou (..)
  , Symbol (..)
  , VarSym (..)
  , Role (..)
  , FunSig (..)
  , Resolved (..)
  , Scope
  , nameKey
  , report
  , reportAll
  , resolveName
  , lookupScope
  , declareIn
  , withLocals
  , inLoop
  , withForVar
  , recordCall
  , recordConstant
  , lookupConstant
  , getConstants
  , canRead
  , canWrite
  , roleWord
  , tshow
  , line
  ) where

import Control.Monad.Reader
import Control.Monad.State.Strict
import qualified Data.Map.Strict as M
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Checked
import Stref.Policy
import Stref.Syntax
import Stref.Types
import Stref.Values (Value)
import Stref.Verification

-- | What a name in a scope stands for.
data Symbol
  = SVar VarSym
  | SFunction FunId FunSig
  | SProgram Text
  deriving (Show)

-- | How a variable was declared; decides whether it may be read or written
-- (MT-VERR-25, MT-VERR-26).
data Role
  = RoleVar
  | RoleConstant -- ^ VAR CONSTANT: written only by its declaration (MT-VAR-5)
  | RoleInput -- ^ VAR_INPUT: read only (MT-PARAM-3)
  | RoleInOut
  | RoleOutput -- ^ VAR_OUTPUT: write only (MT-PARAM-9)
  | RoleSignalIn -- ^ INPUT1..3 (MT-SIG-2)
  | RoleSignalOut -- ^ OUTPUT1..3 (MT-SIG-4)
  | RoleOverflow -- ^ INTERNAL_OVERFLOW (MT-OP-7)
  | RoleResult -- ^ a function's name inside its body (MT-POU-4)
  deriving (Eq, Show)

data VarSym = VarSym
  { vsVar :: Var
  , vsRole :: Role
  , vsMapped :: Bool
  , vsPos :: Pos
  }
  deriving (Show)

data FunSig = FunSig
  { fsName :: Text
  , fsResult :: BasicType
  , fsParams :: [BasicType]
  }
  deriving (Show)

-- | Names are keyed case-insensitively and cut to their significant length
-- (MT-LEX-4, MT-LEX-5).
type Scope = M.Map Text (Symbol, Pos)

-- | The POU whose body is being checked.
data Pou
  = PouNone -- ^ declarations outside any body (global initialisers)
  | PouProgram
  | PouFunction FunId Text Var -- ^ its id, name key, result variable

data Env = Env
  { envPolicies :: Policies
  , envKind :: ModuleKind
  , envGlobals :: Scope
  , envLocals :: Scope
  , envPou :: Pou
  , envLoopDepth :: Int
  , envForVars :: [Var] -- ^ control variables of the enclosing FORs
  }

data St = St
  { stErrors :: [VerificationError]
  , stCalls :: [(FunId, FunId, Pos)] -- ^ caller, callee, call position
  , stConstants :: [(Var, Value)] -- ^ values of CONSTANT variables
  }

type Check = ReaderT Env (State St)

runCheck :: Env -> Check a -> (a, St)
runCheck env m = runState (runReaderT m env) (St [] [] [])

nameKey :: Policies -> Ident -> Text
nameKey p (Ident t) = case pIdentifierLength p of
  Significant n -> T.take n (T.toUpper t)
  Unlimited -> T.toUpper t

report :: Text -> Pos -> Text -> Check ()
report kind pos msg = modify' (\s -> s {stErrors = verificationError kind pos msg : stErrors s})

reportAll :: [VerificationError] -> Check ()
reportAll es = modify' (\s -> s {stErrors = reverse es ++ stErrors s})

recordCall :: FunId -> Pos -> Check ()
recordCall callee pos = do
  pou <- asks envPou
  case pou of
    PouFunction caller _ _ -> modify' (\s -> s {stCalls = (caller, callee, pos) : stCalls s})
    _ -> pure ()

recordConstant :: Var -> Value -> Check ()
recordConstant v x = modify' (\s -> s {stConstants = (v, x) : stConstants s})

lookupConstant :: Var -> Check (Maybe Value)
lookupConstant v = gets (lookup v . stConstants)

getConstants :: Check [(Var, Value)]
getConstants = gets stConstants

lookupScope :: Ident -> Scope -> Check (Maybe (Symbol, Pos))
lookupScope name scope = do
  p <- asks envPolicies
  pure (M.lookup (nameKey p name) scope)

-- | Add a name to a scope; a second declaration of the same name in one
-- scope is an error (MT-SCOPE-4, MT-VERR-7) and leaves the first in place.
declareIn :: Scope -> Pos -> Ident -> Symbol -> Check Scope
declareIn scope pos name sym = do
  p <- asks envPolicies
  let k = nameKey p name
  case M.lookup k scope of
    Just (_, prev) -> do
      report "duplicate-identifier" pos $
        "the identifier " <> identText name <> " is already declared in this scope (line " <> tshow (posLine prev) <> ")"
      pure scope
    Nothing -> pure (M.insert k (sym, pos) scope)

withLocals :: Scope -> Pou -> Check a -> Check a
withLocals scope pou = local (\e -> e {envLocals = scope, envPou = pou, envLoopDepth = 0, envForVars = []})

inLoop :: Check a -> Check a
inLoop = local (\e -> e {envLoopDepth = envLoopDepth e + 1})

withForVar :: Var -> Check a -> Check a
withForVar v = local (\e -> e {envForVars = v : envForVars e})

-- | What a name used in a body denotes.
data Resolved
  = RVar VarSym
  | RFunction FunId FunSig
  | RProgram Text
  | RUndeclared

-- | Resolve a name: the pre-declared signals first (they are reserved
-- words, MT-SIG-1, A20), then a function's own name inside its body (its
-- result), then the global and local scopes in the order of the
-- @name-resolution@ policy (MT-SCOPE-5: the global wins).
resolveName :: Ident -> Check Resolved
resolveName name = do
  env <- ask
  let p = envPolicies env
      k = nameKey p name
      fromScope scope = fmap (toResolved . fst) (M.lookup k scope)
      toResolved = \case
        SVar v -> RVar v
        SFunction i s -> RFunction i s
        SProgram n -> RProgram n
      scoped = case pNameResolution p of
        GlobalWins -> fromScope (envGlobals env) `orElse` fromScope (envLocals env) -- MT-SCOPE-5
        LocalWins -> fromScope (envLocals env) `orElse` fromScope (envGlobals env)
  pure $ case builtinSignal (envPou env) (T.toUpper (identText name)) of
    Just v -> RVar v
    Nothing -> case envPou env of
      PouFunction _ fkey result | fkey == k -> RVar (VarSym result RoleResult False noPos)
      _ -> maybe RUndeclared id scoped
  where
    orElse (Just a) _ = Just a
    orElse Nothing b = b

builtinSignal :: Pou -> Text -> Maybe VarSym
builtinSignal pou n
  | n == "INTERNAL_OVERFLOW" = Just (sig OverflowFlag RoleOverflow) -- MT-SCOPE-9: visible everywhere
  | PouProgram <- pou, Just i <- lookup n [("INPUT" <> tshow j, j) | j <- [1 .. 3]] = Just (sig (SignalInput i) RoleSignalIn)
  | PouProgram <- pou, Just i <- lookup n [("OUTPUT" <> tshow j, j) | j <- [1 .. 3]] = Just (sig (SignalOutput i) RoleSignalOut)
  | otherwise = Nothing
  where
    sig home role = VarSym (Var n (Basic BOOL) home) role False noPos

-- | MT-PARAM-9, MT-SIG-2, MT-SIG-4.
canRead :: Role -> Bool
canRead r = r `notElem` [RoleOutput, RoleSignalOut]

-- | MT-VAR-5, MT-PARAM-3, MT-SIG-2, MT-OP-7.
canWrite :: Role -> Bool
canWrite r = r `notElem` [RoleConstant, RoleInput, RoleSignalIn, RoleOverflow]

roleWord :: Role -> Text
roleWord = \case
  RoleVar -> "a variable"
  RoleConstant -> "a CONSTANT"
  RoleInput -> "a VAR_INPUT parameter"
  RoleInOut -> "a VAR_IN_OUT parameter"
  RoleOutput -> "a VAR_OUTPUT parameter"
  RoleSignalIn -> "a module input signal"
  RoleSignalOut -> "a module output signal"
  RoleOverflow -> "the overflow flag"
  RoleResult -> "the function's result"

tshow :: Show a => a -> Text
tshow = T.pack . show

line :: Pos -> Line
line = posLine
