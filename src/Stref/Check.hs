{-# LANGUAGE MultiWayIf #-}

-- | The verifier (catalogue §§ 2-10): static semantics of MasterTool XE.
-- It reports every verification error it can find (Table 5-1), ordered by
-- position, or elaborates the module into the checked program the
-- interpreter runs: every name bound to its home, every implicit conversion
-- explicit.
module Stref.Check
  ( checkModule
  , dataAreaLimit
  ) where

import Control.Monad (foldM, forM_, unless, void, when)
import Control.Monad.Reader (asks, local)
import Data.Graph (flattenSCC, stronglyConnComp)
import qualified Data.IntMap.Strict as IM
import Data.List (sortOn)
import qualified Data.Map.Strict as M
import Data.Maybe (isJust, mapMaybe)
import Data.Text (Text)
import Stref.Check.Const
import Stref.Check.Monad
import Stref.Check.Stmt
import Stref.Checked
import Stref.Operands
import Stref.Policy (Policies)
import Stref.Syntax
import Stref.Types
import Stref.Values
import Stref.Verification

-- | MT-LIM-3: bytes of unmapped data a module may use.
dataAreaLimit :: Integer
dataAreaLimit = 3072

-- | Check a parsed module as a P or F module; all errors the checker can find.
checkModule :: Policies -> ModuleKind -> Module Pos -> Either [VerificationError] CModule
checkModule policies kind m =
  let env0 = Env policies kind M.empty M.empty PouNone 0 []
      (result, st) = runCheck env0 (checkWhole m)
      errs = sortOn vePos (reverse (stErrors st) ++ recursionErrors (stCalls st))
   in if null errs then Right result else Left errs

-- | MT-POU-8: a cycle in the call graph through a call between two
-- different functions (a function calling itself is reported where it is
-- checked). With declare-before-use no such cycle can be written; the check
-- keeps the guarantee independent of that rule.
recursionErrors :: [(FunId, FunId, Pos)] -> [VerificationError]
recursionErrors calls =
  [ verificationError "recursive-call" pos "this call closes a cycle of function calls; recursion is not allowed"
  | (caller, callee, pos) <- calls
  , caller /= callee
  , sameComponent caller callee
  ]
  where
    -- the call caller -> callee closes a cycle exactly when the caller is
    -- reachable from the callee: both are in one strongly connected
    -- component (linear in the calls, also for long call chains)
    edges = IM.fromListWith (++) [(a, [b]) | (a, b, _) <- calls]
    functions = IM.keys (IM.union (void edges) (IM.fromList [(b, ()) | (_, b, _) <- calls]))
    components = stronglyConnComp [(f, f, IM.findWithDefault [] f edges) | f <- functions]
    componentOf = IM.fromList [(f, i) | (i, c) <- zip [0 :: Int ..] components, f <- flattenSCC c]
    sameComponent a b = IM.lookup a componentOf == IM.lookup b componentOf

-- | Where a block of declarations stands.
data Where = WGlobal | WFunction Text | WProgram Text

-- | One declared variable.
data Declared = Declared
  { dName :: Ident
  , dPos :: Pos
  , dVar :: Var
  , dRole :: Role
  , dMapped :: Bool
  , dSection :: VarSection
  , dInit :: Maybe InitValue
  }


-- | The entry of 'cmInits' (or a function's locals) for a variable: unmapped
-- ones always, mapped ones only with an initialiser (MT-VAR-3, A3).
initOf :: Declared -> Maybe VarInit
initOf d
  | dMapped d && not (isJust (dInit d)) = Nothing
  | otherwise = Just (VarInit (dVar d) (dInit d))

checkWhole :: Module Pos -> Check CModule
checkWhole (Module globals functions program) = do
  forM_ globals $ \b ->
    when (vbSection b /= SecVar) $
      report "misplaced-parameter-section" (vbAnn b) "parameter sections belong to the PROGRAM; global variables are declared in VAR ... END_VAR"
  (gscope, slot1, gdecls) <- declareVars WGlobal Data M.empty 0 globals
  (gscope', funs, fdecls) <- foldM checkFunction (gscope, [], []) (zip [0 ..] functions)
  gscope'' <- declareIn gscope' (prAnn program) (prName program) (SProgram (identText (prName program))) -- MT-POU-13
  (cprog, slot2, pdecls) <- local (\e -> e {envGlobals = gscope''}) (checkProgram slot1 program)
  let unmappedBytes = [(dPos d, typeBytes (varType (dVar d))) | d <- gdecls ++ fdecls ++ pdecls, not (dMapped d)]
      total = sum (map snd unmappedBytes)
  checkDataArea unmappedBytes
  let progName = identText (prName program)
      named =
        [(identText (dName d), dVar d) | d <- gdecls]
          ++ [(progName <> "." <> identText (dName d), dVar d) | d <- pdecls]
  pure
    CModule
      { cmFunctions = IM.fromList (zip [0 ..] (reverse funs))
      , cmDataSize = slot2
      , cmInits = mapMaybe initOf (gdecls ++ pdecls)
      , cmMapped = [dVar d | d <- gdecls ++ fdecls ++ pdecls, dMapped d]
      , cmNamed = named
      , cmProgram = cprog
      , cmDataBytes = total
      }

-- | MT-LIM-3, A26, MT-VERR-43: the sum of the unmapped variables' sizes.
checkDataArea :: [(Pos, Integer)] -> Check ()
checkDataArea sizes =
  case dropWhile ((<= dataAreaLimit) . snd) (zip (map fst sizes) (scanl1 (+) (map snd sizes))) of
    ((pos, _) : _) ->
      report "data-area-exceeded" pos $
        "the unmapped variables need " <> tshow (sum (map snd sizes)) <> " bytes of data area; the limit is " <> tshow dataAreaLimit <> " bytes (this declaration crosses it)"
    [] -> pure ()

checkFunction :: (Scope, [CFunction], [Declared]) -> (FunId, Function Pos) -> Check (Scope, [CFunction], [Declared])
checkFunction (gscope, funs, declsAcc) (fid, Function pos name result blocks body) = do
  p <- asks envPolicies
  let key = nameKey p name
      resultVar = Var (identText name) (Basic result) (Frame 0)
      resultScope = M.singleton key (SVar (VarSym resultVar RoleResult False pos), pos)
  forM_ blocks $ \b ->
    when (vbSection b `elem` [SecInOut, SecOutput]) $
      report "function-parameter-kind" (vbAnn b) ("the function " <> identText name <> " may only have VAR_INPUT parameters, not VAR_IN_OUT or VAR_OUTPUT") -- MT-POU-7, MT-VERR-36
  (lscope, frameSize, decls) <- local (\e -> e {envGlobals = gscope}) (declareVars (WFunction (identText name)) Frame resultScope 1 blocks)
  let params = [d | d <- decls, dSection d == SecInput]
      sig = FunSig (identText name) result [varBasicType (dVar d) | d <- params]
  when (null params) $
    report "function-without-input" pos ("the function " <> identText name <> " needs at least one VAR_INPUT parameter") -- MT-POU-3
  gscope' <- declareIn gscope pos name (SFunction fid sig) -- MT-SCOPE-2
  body' <- local (\e -> e {envGlobals = gscope'}) $ withLocals lscope (PouFunction fid key resultVar) (checkBody pos body)
  case missingReturn (\n -> nameKey p n == key) body of
    Just at ->
      report "missing-return-value" (maybe pos id at) ("a path through the function " <> identText name <> " ends without assigning its result") -- MT-POU-4, MT-VERR-18
    Nothing -> pure ()
  let cf =
        CFunction
          { cfName = identText name
          , cfLine = line pos
          , cfResult = result
          , cfParams = map dVar params
          , cfLocals = mapMaybe initOf [d | d <- decls, dSection d == SecVar]
          , cfFrameSize = frameSize
          , cfBody = body'
          }
  pure (gscope', cf : funs, declsAcc ++ decls)

-- | At least one statement (MT-POU-3, MT-POU-12); a lone @;@ counts.
checkBody :: Pos -> [Stmt Pos] -> Check [CStmt]
checkBody pos body = do
  when (null body) $ report "missing-statement" pos "a FUNCTION or PROGRAM needs at least one statement (a lone ; will do)"
  checkStmts body

checkProgram :: Int -> Program Pos -> Check (CProgram, Int, [Declared])
checkProgram slot0 (Program pos name blocks body) = do
  kind <- asks envKind
  forM_ blocks $ \b ->
    when (kind == ProcedureModule && vbSection b /= SecVar) $
      report "procedure-parameters" (vbAnn b) "a procedure (P) module takes no parameters; VAR_INPUT, VAR_IN_OUT and VAR_OUTPUT need a function (F) module" -- MT-PARAM-2, MT-VERR-35
  (pscope, slot, decls) <- declareVars (WProgram (identText name)) Data M.empty slot0 blocks
  let inputs = [d | d <- decls, dSection d `elem` [SecInput, SecInOut]]
      outputs = [d | d <- decls, dSection d == SecOutput]
  when (kind == FunctionModule) $ do
    -- MT-PARAM-1: at most 10 CHF inputs and 10 outputs
    case drop 10 inputs of
      (d : _) -> report "too-many-inputs" (dPos d) "an F module can have at most 10 VAR_INPUT and VAR_IN_OUT parameters together" -- MT-VERR-33
      [] -> pure ()
    case drop 10 outputs of
      (d : _) -> report "too-many-outputs" (dPos d) "an F module can have at most 10 VAR_OUTPUT parameters" -- MT-VERR-34
      [] -> pure ()
  body' <- withLocals pscope PouProgram (checkBody pos body)
  let cp =
        CProgram
          { cpName = identText name
          , cpInputs = [dVar d | d <- decls, dSection d == SecInput]
          , cpInOuts = [dVar d | d <- decls, dSection d == SecInOut]
          , cpOutputs = map dVar outputs
          , cpBody = body'
          }
  pure (cp, slot, decls)

-- | Declare the variables of some blocks, one declaration after another (a
-- declaration may use the CONSTANTs before it), giving each unmapped
-- variable its slots from @mkHome@.
declareVars :: Where -> (Int -> Home) -> Scope -> Int -> [VarBlock Pos] -> Check (Scope, Int, [Declared])
declareVars wh mkHome scope0 slot0 blocks = go scope0 slot0 [] [(b, d) | b <- blocks, d <- vbDecls b]
  where
    go scope slot acc [] = pure (scope, slot, reverse acc)
    go scope slot acc ((b, d) : rest) = do
      (ds, slot') <- withScope scope (declOne wh mkHome slot b d)
      scope' <- foldM (\sc dcl -> declareIn sc (dPos dcl) (dName dcl) (SVar (VarSym (dVar dcl) (dRole dcl) (dMapped dcl) (dPos dcl)))) scope ds
      go scope' slot' (reverse ds ++ acc) rest
    withScope :: Scope -> Check a -> Check a
    withScope sc = case wh of
      WGlobal -> local (\e -> e {envGlobals = sc})
      _ -> local (\e -> e {envLocals = sc})

declOne :: Where -> (Int -> Home) -> Int -> VarBlock Pos -> VarDecl Pos -> Check ([Declared], Int)
declOne wh mkHome slot0 block (VarDecl dpos names at tspec initz) = do
  ty <- checkTypeSpec tspec
  let section = vbSection block
      elemT = elementType ty
      role = case section of
        SecVar -> if vbConstant block then RoleConstant else RoleVar
        SecInput -> RoleInput
        SecInOut -> RoleInOut
        SecOutput -> RoleOutput
  -- parameter types (MT-POU-6, MT-PARAM-8, MT-VERR-32)
  case (wh, section) of
    (WFunction fname, SecInput)
      | Array {} <- ty -> report "invalid-parameter-type" dpos ("an array cannot be a parameter of the function " <> fname)
    (WProgram pname, s)
      | s /= SecVar, elemT == BOOL -> report "invalid-parameter-type" dpos (typeText ty <> " cannot be a parameter of the program " <> pname)
    _ -> pure ()
  operand <- case at of
    Nothing -> pure Nothing
    Just (apos, ref) -> checkMapping wh section apos ref ty
  value <- checkInitializer ty initz
  let place (slot, acc) (npos, ident) =
        let (home, slot') = case operand of
              Just op -> (Mapped op, slot)
              Nothing -> (mkHome slot, slot + fromInteger (elementCount ty))
            var = Var (identText ident) ty home
         in (slot', Declared ident npos var role (isJust operand) section value : acc)
      (slotN, declsRev) = foldl place (slot0, []) names
      decls = reverse declsRev
  -- the values of CONSTANTs, for labels, bounds and later initialisers
  when (role == RoleConstant) $
    forM_ decls $ \d -> case (dInit d, ty) of
      (Just (InitScalar v), _) -> recordConstant (dVar d) v
      (Nothing, Basic t) | not (dMapped d) -> recordConstant (dVar d) (defaultValue t) -- MT-VAR-7
      _ -> pure ()
  pure (decls, slotN)

elementCount :: Type -> Integer
elementCount = \case
  Basic _ -> 1
  Array lo hi _ -> hi - lo + 1

typeText :: Type -> Text
typeText = \case
  Basic t -> typeName t
  Array lo hi t -> "ARRAY[" <> tshow lo <> ".." <> tshow hi <> "] OF " <> typeName t

-- | A type as declared; array bounds are integer constants with
-- 0 <= lower <= upper (MT-ARR-1, MT-ARR-4). A bad array keeps one element
-- so that its uses are still checked.
checkTypeSpec :: TypeSpec Pos -> Check Type
checkTypeSpec = \case
  TBasic t -> pure (Basic t)
  TArray loE hiE t -> do
    lo <- constInteger loE
    hi <- constInteger hiE
    case (lo, hi) of
      (Just a, Just b)
        | a < 0 -> do
            report "value-out-of-limits" (exprAnn loE) ("the lower bound " <> tshow a <> " of an array cannot be negative") -- MT-ARR-4, MT-VERR-37
            pure (Array 0 0 t)
        | a > b -> do
            report "min-greater-than-max" (exprAnn loE) ("the array bounds " <> tshow a <> ".." <> tshow b <> " have the minimum above the maximum") -- MT-ARR-4, MT-VERR-38
            pure (Array a a t)
        | b - a + 1 > maxArrayElements -> do
            report "invalid-array-size" (exprAnn loE) ("an array can have at most " <> tshow maxArrayElements <> " elements") -- MT-VERR-44
            pure (Array a a t)
        | otherwise -> pure (Array a b t)
      _ -> pure (Array 0 0 t)

-- | The largest element count an operand range can hold (addresses 0..65535).
maxArrayElements :: Integer
maxArrayElements = 65536

-- | An @AT@ clause (MT-MAP-2..12): only in VAR blocks, a valid operand, and a
-- type Table 4-8 allows; mapped arrays are not BOOL.
checkMapping :: Where -> VarSection -> Pos -> OperandRef -> Type -> Check (Maybe Operand)
checkMapping wh section apos ref ty
  | section /= SecVar = do
      case wh of
        WFunction fname -> report "invalid-parameter-type" apos ("a parameter of the function " <> fname <> " cannot be mapped to a PLC operand") -- MT-POU-6
        _ -> report "mapping-not-allowed" apos "AT is only allowed in VAR blocks, not for parameters" -- MT-MAP-4
      pure Nothing
  | otherwise = case resolveOperand ref of
      Left problem -> do
        report "invalid-operand" apos ("the operand is not valid: " <> describeOperandProblem problem) -- MT-VERR-39
        pure Nothing
      Right op
        | Array _ _ BOOL <- ty -> do
            incompatible op "a BOOL array (mapped arrays cannot be BOOL)" -- MT-MAP-11
            pure (Just op)
        | not (compatibleType op (elementType ty)) -> do
            incompatible op (typeText ty) -- MT-MAP-5, MT-MAP-12
            pure (Just op)
        | otherwise -> pure (Just op)
  where
    incompatible op what =
      report "incompatible-operand" apos ("the PLC operand " <> renderOperand op <> " is incompatible with " <> what) -- MT-VERR-31

-- | An initial value (MT-VAR-4, MT-ARR-6, MT-ARR-7).
checkInitializer :: Type -> Maybe (Initializer Pos) -> Check (Maybe InitValue)
checkInitializer ty = \case
  Nothing -> pure Nothing
  Just (InitExpr e) -> case ty of
    Basic t -> fmap InitScalar <$> constValueAt t e
    Array {} -> do
      report "invalid-initializer" (exprAnn e) "an array is initialised with a list of values in brackets, e.g. [1, 2, 3]"
      pure Nothing
  Just (InitList pos es) -> case ty of
    Basic _ -> do
      report "invalid-initializer" pos "a list of values can only initialise an array"
      pure Nothing
    Array lo hi t -> do
      vs <- mapM (constValueAt t) es
      let n = hi - lo + 1
      unless (fromIntegral (length es) == n) $
        report "wrong-initializer-count" pos ("the array has " <> tshow n <> " elements but the list gives " <> tshow (length es) <> " values") -- MT-ARR-7, MT-VERR-30
      pure (InitArray <$> sequence vs)

