{-# LANGUAGE FlexibleContexts #-}

-- | The checker of an IEC compilation unit: resolves names and types, gives
-- untyped literals the type of their context (TC-CONV-4), checks the rules a
-- compiler enforces (docs/tecomat.md, "Compile-time errors") and computes
-- initial values. The result is the 'Program' the evaluator runs.
module Stref.IEC.Check
  ( checkUnit
  , ProgramChoice (..)
  , locationType
  , standardFunctionNames
  ) where

import Control.Monad (foldM, forM, forM_, unless, when)
import Control.Monad.Except (Except, catchError, runExcept, throwError)
import Control.Monad.Reader (ReaderT, asks, local, runReaderT)
import Data.List (find, sortOn)
import qualified Data.Map.Lazy as ML
import qualified Data.Map.Strict as M
import Data.Maybe (catMaybes, fromMaybe, isJust, isNothing)
import qualified Data.Sequence as Seq
import qualified Data.Set as Set
import qualified Data.Set as S
import Control.Applicative ((<|>))
import Data.Text (Text)
import qualified Data.Text as T
import Stref.IEC.Checked
import Stref.IEC.Conversions (conversionName, convert)
import Stref.IEC.Dialect.MasterTool (SignalUse (..), dataAreaLimit, dataBytes, elementaryTypes, hasConversion, operandTakes, reservedWord, signalUse)
import Stref.IEC.Memory (layout, sizeInBytes)
import Stref.IEC.Operators (binary, binaryType, fitsUnder, unary, unaryType)
import Stref.IEC.Standard (libraryFunction, shiftNames, standardParameters, standardType)
import Stref.IEC.StandardFB (libraryTypes, standardFBNames, standardFBs)
import Stref.IEC.Syntax
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy
import Stref.Verification (VerificationError (..))

-- | Which programs run: the ones of the configuration, one named, or the
-- file's only PROGRAM.
data ProgramChoice
  = ProgramsOfConfiguration -- ^ the configuration's, or the file's only PROGRAM
  | ProgramNamed Text
  | AllPrograms -- ^ every PROGRAM, each as one instance (for checking a file)
  deriving (Eq, Show)

data Env = Env
  { envPol :: Policies
  , envTypes :: M.Map Text TypeDecl
  , envPackModes :: M.Map Text Integer -- ^ NX-PRAGMA-11
  , envPous :: M.Map Text Pou -- ^ user POUs
  , envStd :: M.Map Text PouDef -- ^ standard FBs
  , envVarsOf :: M.Map Text [VarInfo] -- ^ the resolved variables of every user POU (lazy)
  , envGlobals :: M.Map Text VarInfo
  , envPou :: Maybe Pou -- ^ the POU being checked
  , envLocals :: M.Map Text VarInfo
  , envLoop :: Bool
  , envLabels :: Set.Set Text -- ^ the labels of the enclosing blocks (NX-STMT-42)
  , envSelf :: Maybe Text -- ^ the FB or program whose instance the code runs on (its body, methods, actions)
  , envInstanceVars :: M.Map Text VarInfo -- ^ in a method: the variables of its instance (NX-POU-27, NX-POU-29)
  , envMembersOf :: M.Map Text (M.Map Text (PouKind, [VarInfo])) -- ^ the methods, accessors and actions every POU declares (lazy)
  , envGvls :: M.Map Text (M.Map Text VarInfo) -- ^ CODESYS: the named global lists, for @GVL.x@ (NX-VAR-35)
  , envQualifiedOnly :: Set.Set Text -- ^ globals of a qualified_only list (NX-PRAGMA-10)
  , envAmbiguous :: Set.Set Text -- ^ globals that several lists declare (NX-LEX-9)
  , envProgramInstance :: M.Map Text Text -- ^ each PROGRAM's instance, by the program's key
  , envStatic :: Text -- ^ where the running POU's VAR_STAT lie: the prefix of their global keys
  , envTypeDepth :: Int
  , envForVars :: [Text] -- ^ MasterTool: the control variables of the enclosing FORs (MT-STMT-20)
  }

type C = ReaderT Env (Except VerificationError)

failC :: Text -> Pos -> Text -> C a
failC k p m = throwError (VerificationError k p m)

-- | Whether the unit is a MasterTool XE module (the preset's source form),
-- whose verifier has rules of its own (MT-VERR, Table 5-1).
masterToolSource :: C Bool
masterToolSource = asks ((== MasterToolSource) . pSourceForm . envPol)

-- | NX-ERR-1, NX-ERR-2: the implicit check functions, called where the
-- manual says when the program declares them.
checkFunctionNames :: [Text]
checkFunctionNames = ["CHECKBOUNDS", "CHECKDIVINT", "CHECKDIVDINT", "CHECKDIVLINT", "CHECKDIVREAL", "CHECKDIVLREAL", "CHECKRANGESIGNED", "CHECKRANGEUNSIGNED", "CHECKPOINTER"]

-- | Standard function names (Tab.3.12-3.19), reserved for user names
-- (TC-LEX-3).
standardFunctionNames :: [Text]
standardFunctionNames =
  [ "ABS", "SQRT", "LN", "LOG", "EXP", "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ADD", "MUL", "SUB", "DIV", "MOD", "EXPT", "MOVE"
  , "SHL", "SHR", "ROR", "ROL", "AND", "OR", "XOR", "NOT", "SEL", "MAX", "MIN", "LIMIT", "MUX", "GT", "GE", "EQ", "LE", "LT", "NE"
  , "LEN", "LEFT", "RIGHT", "MID", "CONCAT", "INSERT", "DELETE", "REPLACE", "FIND", "TRUNC"
  ]

-- | TC-LEX-1, TC-LEX-3 (and TC-LEX-4, taken literally): elementary type
-- names, standard functions and FBs, and the names of their parameters are
-- not user names.
reservedName :: Policies -> Text -> Bool
reservedName pol n =
  let u = key n
   in if pSourceForm pol == MasterToolSource then reservedWord pol u else isJust (parseElemName u) || isJust (conversionName pol u)
        || case pReservedNames pol of
          ReservedIec ->
            u `elem` standardFunctionNames || u `elem` standardFBNames || u `elem` standardParameterNames
              || (("IN" `T.isPrefixOf` u) && T.length u > 2 && T.all (`elem` ['0' .. '9']) (T.drop 2 u))
          ReservedCodesys -> u `elem` codesysReserved -- NX-LEX-12

-- | Which names 'reservedName' keeps from what, with the dialect's rules.
reservedWhy :: Policies -> Text -> Text
reservedWhy pol what = case pReservedNames pol of
  ReservedIec -> "elementary types, standard functions and standard function blocks cannot name " <> what <> " (TC-LEX-1, TC-LEX-3)"
  ReservedCodesys -> "elementary types, conversion operators and the words of the manual's keyword list (operators, IL instructions, ADR, SIZEOF, ...) cannot name " <> what <> " (NX-LEX-12, NX-LEX-13)"

-- | NX-LEX-12: the words of the manual's list that are not keywords of the
-- grammar already (IL operators, operators named like functions).
codesysReserved :: [Text]
codesysReserved =
  [ "ABS", "ACOS", "ADD", "AND", "ASIN", "ATAN", "COS", "DIV", "EQ", "EXP", "EXPT", "GE", "GT", "LE", "LN", "LOG", "LT", "MAX", "MIN"
  , "MOD", "MOVE", "MUL", "MUX", "NE", "NOT", "OR", "ROL", "ROR", "SEL", "SHL", "SHR", "SIN", "SQRT", "SUB", "TAN", "TRUNC", "XOR"
  , "ADR", "BITADR", "CAL", "CALC", "CALCN", "INDEXOF", "JMPC", "JMPCN", "LD", "LDN", "PARAMS", "R", "READ_ONLY", "READ_WRITE"
  , "RET", "RETC", "RETCN", "S", "SIZEOF", "ST", "STN", "BIT", "LTIME"
  ]

-- | The parameters of the standard functions (Tab.3.12-3.19) and FBs
-- (Tab.3.22).
standardParameterNames :: [Text]
standardParameterNames = ["IN", "N", "L", "P", "G", "K", "MN", "MX", "S", "S1", "R", "R1", "CLK", "Q", "Q1", "CU", "CD", "LD", "PV", "QU", "QD", "CV", "PT", "ET"]

checkUnit :: Policies -> ProgramChoice -> Unit -> Either VerificationError Program
checkUnit pol choice (Unit decls) = runExcept $ do
  let typeDecls = concat [ts | DTypes ts <- decls]
      pous = [p | DPou p <- decls]
      configs = [c | DConfig c <- decls]
      -- MT-POU-1: a MasterTool module's VAR blocks before its POUs are its globals
      globalBlocks = [if pSourceForm pol == MasterToolSource && vbSection b == SecVar then b {vbSection = SecGlobal} else b | DGlobals b <- decls] ++ concat [cfgGlobals c ++ concatMap resGlobals (cfgResources c) | c <- configs]
      -- a POU of the unit hides a library FB of its name (the library's
      -- FBs beyond IEC's are not reserved names)
      std = M.fromList [(k, d) | (k, d) <- standardFBs pol, k `notElem` map (key . pouName) pous]
  -- duplicates and reserved names among the declared names
  let topNames = [(tdPos t, tdName t) | t <- typeDecls] ++ [(pouPos p, pouName p) | p <- pous]
  forM_ topNames $ \(p, n) -> when (reservedName pol n) (throwError (VerificationError "reserved-name" p (reservedMessage n)))
  checkDuplicates topNames
  -- NX-PRAGMA-11: pack_mode takes 0, 1, 2, 4 or 8, on a type or a POU
  let packed = [(tdPos t, tdName t, v) | t <- typeDecls, Just v <- [attributeValue "pack_mode" (tdAttributes t)]]
        ++ [(pouPos p, pouName p, v) | p <- pous, Just v <- [attributeValue "pack_mode" (pouAttributes p)]]
  packModes <- fmap M.fromList . forM packed $ \(at, n, v) ->
    case readMaybeInt v of
      Just m | m `elem` [0, 1, 2, 4, 8] -> pure (key n, m)
      _ -> throwError (VerificationError "value-out-of-limits" at ("pack_mode is 0, 1, 2, 4 or 8, not '" <> v <> "' (NX-PRAGMA-11)"))
  checkRecursion pol True pous globalBlocks -- before instances are built from their declarations
  let envBase =
        Env
          { envPol = pol
          , envTypes = M.fromList [(key (tdName t), t) | t <- libraryTypes pol ++ typeDecls]
          , envPackModes = packModes
          , envPous = M.fromList [(key (pouName p), p) | p <- pous]
          , envStd = std
          , envVarsOf = M.empty
          , envGlobals = M.empty
          , envPou = Nothing
          , envLocals = M.empty
          , envLoop = False
          , envLabels = Set.empty
          , envSelf = Nothing
          , envInstanceVars = M.empty
          , envMembersOf = M.empty
          , envGvls = M.empty
          , envQualifiedOnly = Set.empty
          , envAmbiguous = Set.empty
          , envProgramInstance = M.empty
          , envStatic = ""
          , envTypeDepth = 0
          , envForVars = []
          }
  -- global CONSTANTs, which declarations may use (array bounds, initial
  -- values: TC-VAR-18, TC-VAR-31); computed before the POUs' variables
  constants <- runReaderT (concat <$> mapM (blockVars Nothing) [b | b <- globalBlocks, vbConstant b]) envBase
  forM_ pous (checkInheritance (M.fromList [(key (pouName p), p) | p <- pous]))
  let env0 = envBase {envGlobals = M.fromList [(viKey v, v) | v <- constants], envVarsOf = varsOf, envMembersOf = membersOf}
      -- the variables of every POU, resolved once; laziness lets an FB's
      -- instance value use the variables of the FBs it contains
      varsOfE = ML.fromList [(key (pouName p), runExcept (runReaderT (pouVariables p) env0)) | p <- pous]
      varsOf = ML.map (either (const []) id) varsOfE
      membersOfE = ML.fromList [(key (pouName p), runExcept (runReaderT (memberSignatures p) env0)) | p <- pous]
      membersOf = ML.map (either (const M.empty) id) membersOfE
  -- report the first error in a POU's declarations
  forM_ pous $ \p -> either throwError (const (pure ())) (varsOfE M.! key (pouName p))
  forM_ pous $ \p -> either throwError (const (pure ())) (membersOfE M.! key (pouName p))
  -- every TYPE is checked, also one that only a pointer names (TNamed is
  -- looked up only where a pointer is followed)
  forM_ typeDecls $ \t -> runReaderT (resolveType (TSName (tdPos t) (tdName t))) env0
  perBlock <- forM globalBlocks $ \b -> do
    vs <- runReaderT (blockVars Nothing b) env0
    checkDuplicates [(viPos v, viName v) | v <- vs]
    pure (b, vs)
  gvls <- globalLists perBlock
  -- MT-SCOPE-2, MT-POU-13 (MT-VERR-7): a MasterTool module's functions and
  -- its program are names of the global scope
  when (pSourceForm pol == MasterToolSource) $
    forM_ pous $ \p -> when (key (pouName p) `elem` [key (viName v) | (_, vs) <- perBlock, v <- vs]) $
      throwError (VerificationError "duplicate-identifier" (pouPos p) ("'" <> pouName p <> "' is declared already as a global variable (MT-VERR-7)"))
  let globals = [v | (_, _, vs) <- gvls, v <- vs]
      unqualified = M.fromList [(key (viName v), v) | (_, False, vs) <- gvls, v <- vs, not (clashes v)]
      clashes v = viKey v /= key (viName v)
      env1 =
        env0
          { envGlobals = unqualified
          , envGvls = M.fromList [(key n, M.fromList [(key (viName v), v) | v <- vs]) | (Just n, _, vs) <- gvls]
          , envQualifiedOnly = Set.fromList [key (viName v) | (_, True, vs) <- gvls, v <- vs]
          , envAmbiguous = Set.fromList [key (viName v) | v <- globals, clashes v]
          }
  instances <- case choice of
    AllPrograms -> pure [(pouName p, key (pouName p)) | p <- pous, pouKind p == KProgram]
    ProgramNamed n -> case find ((== key n) . key . pouName) pous of
      Just p | pouKind p == KProgram -> pure [(pouName p, key (pouName p))]
      _ -> throwError (VerificationError "undeclared-program" (Pos 1 1) ("the case names the program " <> n <> ", which the file does not declare"))
    ProgramsOfConfiguration -> case configs of
      (c : _) -> forM (orderedPrograms c) $ \pc -> case M.lookup (key (pcType pc)) (M.fromList [(key (pouName p), p) | p <- pous]) of
        Just p | pouKind p == KProgram -> pure (pcInstance pc, key (pouName p))
        _ -> throwError (VerificationError "undeclared-program" (pcPos pc) ("the configuration runs " <> pcType pc <> ", which is not a PROGRAM of the file"))
      [] -> case [p | p <- pous, pouKind p == KProgram] of
        [p] -> pure [(pouName p, key (pouName p))]
        [] -> throwError (VerificationError "no-program" (Pos 1 1) "the file has no PROGRAM to run")
        (_ : p : _) -> throwError (VerificationError "several-programs" (pouPos p) "the file has several PROGRAMs and no CONFIGURATION: say which one runs")
  -- NX-VAR-26..28: the globals' computed initial values, list by list in
  -- the order of global_init_slot (default 50000, lower first); a value
  -- may use the globals of its own list declared before it and those of
  -- lists with a lower slot, else the order is undefined: a compile error
  let slotOf b = maybe 50000 (\t -> fromMaybe 50000 (readMaybeInt t)) (attributeValue "global_init_slot" (vbAttributes b))
      ordered = sortOn (\(i, (b, _)) -> (slotOf b, i)) (zip [0 :: Int ..] perBlock)
  globalInits <- fmap concat . forM ordered $ \(_, (b, vs)) -> do
    inits <- runReaderT (checkInits [(b, d) | d <- vbDecls b]) env1
    let mine = map (key . viName) vs
        earlierOk k = k `elem` mine || slotOf b > maybe 50000 slotOf (lookup k [(key (viName v), bb) | (bb, bvs) <- perBlock, v <- bvs])
    forM_ inits $ \(k, _, ce) -> forM_ (globalsRead ce) $ \g ->
      unless (earlierOk g) $ throwError (VerificationError "global-init-order" (cePos ce) ("the initial value of " <> k <> " uses " <> g <> " of another global list that is not initialised first; give that list a lower global_init_slot (NX-VAR-27, NX-VAR-28)"))
    pure [(maybe k id (lookup k [(key (viName v), viKey v) | (_, _, vs) <- gvls, v <- vs]), t, ce) | (k, t, ce) <- inits]
  globalInitArgs <- fmap M.unions . forM perBlock $ \(b, _) -> do
    args <- runReaderT (checkInitArgs (vbDecls b)) env1
    pure (M.mapKeys (\k -> maybe k id (lookup k [(key (viName v), viKey v) | (_, _, vs) <- gvls, v <- vs])) args)
  -- NX-POU-1..4: every PROGRAM has one instance, the configuration's or
  -- its own name's, which the tasks run and other POUs may call
  let programRoots = instances ++ [(pouName p, key (pouName p)) | p <- pous, pouKind p == KProgram, key (pouName p) `notElem` map snd instances]
      env2 = env1 {envProgramInstance = M.fromList [(t, key inst) | (inst, t) <- reverse programRoots]}
  defs <- forM pous $ \p -> runReaderT (checkPou p) env2 {envPou = Just p, envLocals = M.fromList [(viKey v, v) | v <- varsOf M.! key (pouName p)], envSelf = selfOf p, envStatic = staticPrefix (pouName p)}
  -- NX-VAR-10: the VAR_STAT of every POU and method, stored as globals
  let statics =
        [v {viKey = staticPrefix (pouName p) <> viKey v} | p <- pous, v <- varsOf M.! key (pouName p), viSection v == SecStat]
          ++ [v {viKey = staticPrefix (pouName p <> "." <> m) <> viKey v} | p <- pous, (m, (_, vs)) <- M.toList (membersOf M.! key (pouName p)), v <- vs, viSection v == SecStat]
  checkRecursion pol False pous globalBlocks
  -- MT-LIM-3, A26 (MT-VERR-43): a MasterTool module's unmapped variables,
  -- the globals', the functions', then the program's, fit the data area;
  -- the declaration that crosses the limit is the error
  when (pSourceForm pol == MasterToolSource) $ do
    let ownVars p = [v | v <- varsOf M.! key (pouName p), viKey v /= key (pouName p) || viSection v /= SecOutput]
        unmapped =
          [v | (_, vs) <- perBlock, v <- vs, isNothing (signalUse (viKey v))]
            ++ concat [ownVars p | p <- pous, pouKind p == KFunction]
            ++ concat [ownVars p | p <- pous, pouKind p == KProgram]
        used = scanl1 (+) [dataBytes (viType v) | v <- unmapped, isNothing (viAt v)]
    case [v | (v, n) <- zip [v | v <- unmapped, isNothing (viAt v)] used, n > dataAreaLimit] of
      v : _ -> throwError (VerificationError "data-area-exceeded" (viPos v) ("the unmapped variables need " <> T.pack (show (last used)) <> " bytes of data area; the limit is " <> T.pack (show dataAreaLimit) <> " bytes, and this declaration crosses it (MT-VERR-43)"))
      [] -> pure ()
  varConfig <- runReaderT (checkVarConfig pous varsOf ([(inst, TProgram t) | (inst, t) <- programRoots] ++ [(viName g, viType g) | g <- globals]) (concat [es | DVarConfig es <- decls])) env2
  forM_ configs $ \c -> forM_ (cfgResources c) $ \r ->
    when (T.null (resName r)) $ case map taskPos (resTasks r) ++ map pcPos (resPrograms r) of
      (tp : _) -> throwError (VerificationError "section-not-allowed" tp "TASK and PROGRAM ... WITH stand inside a RESOURCE ... END_RESOURCE (TC-CFG-8, TC-CFG-12)")
      [] -> pure ()
  -- TC-CFG-10: PROGRAM ... WITH names a task of its resource
  forM_ configs $ \c -> forM_ (cfgResources c) $ \r -> forM_ (resPrograms r) $ \pc -> case pcTask pc of
    Just t | key t `notElem` map (key . taskName) (resTasks r) ->
      throwError (VerificationError "undeclared-task" (pcPos pc) ("the program " <> pcInstance pc <> " is associated with " <> t <> ", which is not a TASK of its resource (TC-CFG-10)"))
    _ -> pure ()
  interval <- case configs of
    (c : _) -> pure (taskInterval c)
    [] -> pure Nothing
  pure
    Program
      { prPous = M.union (M.fromList [(key (pdName d), d) | d <- defs]) std
      , prGlobals = globals ++ statics
      , prInstances = instances
      , prRoots = programRoots
      , prTaskInterval = interval
      , prPeriods = case (choice, configs) of
          (ProgramsOfConfiguration, c : _) -> M.fromList [(key (pcInstance pc), ms) | r <- cfgResources c, pc <- resPrograms r, Just ms <- [periodOf r pc]]
          _ -> M.empty
      , prGvls = M.fromList [(key n, M.fromList [(key (viName v), viKey v) | v <- vs]) | (Just n, _, vs) <- gvls]
      , prGlobalInits = globalInits
      , prGlobalInitArgs = globalInitArgs
      , prPackModes = packModes
      , prVarConfig = varConfig
      , prTimeRange = pTimeRange pol
      , prChecks = if pExtensions pol == ExtensionsCodesys then [key (pouName p) | p <- pous, pouKind p == KFunction, key (pouName p) `elem` checkFunctionNames] else []
      }
  where
    staticPrefix n = "$STAT." <> key n <> "."
    selfOf p = if pouKind p `elem` [KFunctionBlock, KProgram] then Just (key (pouName p)) else Nothing
    reservedMessage n = "'" <> n <> "' is reserved: " <> reservedWhy pol "user declarations"

-- | NX-VAR-14: VAR_CONFIG gives each instance's variable declared at an
-- incomplete address (%I*, %Q*) its address, by the instance's full path;
-- the class (input, output) and the type must agree, a path that names no
-- such variable is an error, and so is such a variable left without one.
-- The result: the class, the path, the address and the type of each.
checkVarConfig :: [Pou] -> M.Map Text [VarInfo] -> [(Text, Type)] -> [ConfigEntry] -> C [(Char, [Step], Location, Type)]
checkVarConfig pous varsOf roots entries = do
  let open = M.fromList [(key (pouName p), [(n, locArea l, vdPos d) | vb <- pouVars p, d <- vbDecls vb, Just l <- [vdAt d], incomplete l, (_, n) <- vdNames d]) | p <- pous, pouKind p == KFunctionBlock]
      typeOf fb k = maybe (TElem BOOL) viType (find ((== k) . viKey) (M.findWithDefault [] fb varsOf))
      instancesIn n = [v | v <- M.findWithDefault [] (key n) varsOf, isInstance (viType v)]
      isInstance = \case
        TFB _ -> True
        _ -> False
      -- every path to such a variable, through the FB instances
      -- (names as declared; compared by key)
      walk :: Int -> [Text] -> Type -> [([Text], Char, Type, Pos)]
      walk depth path t
        | depth > 32 = []
        | otherwise = case t of
            TFB n -> [(path ++ [k], area, typeOf (key n) (key k), p) | (k, area, p) <- M.findWithDefault [] (key n) open] ++ inner n
            TProgram n -> inner n
            _ -> []
        where
          inner n = concat [walk (depth + 1) (path ++ [viName v]) (viType v) | v <- instancesIn n]
      wanted = concat [walk 0 [r] t | (r, t) <- roots]
      dotted = T.intercalate "."
  configured <- forM entries $ \e -> do
    let path = map key (cfgEntryPath e)
        at = cfgEntryAt e
        here = cfgEntryPos e
    case find (\(p, _, _, _) -> map key p == path) wanted of
      Nothing -> failC "undeclared-variable" here ("VAR_CONFIG names " <> dotted (cfgEntryPath e) <> ", which is no instance's variable declared at %I* or %Q* (NX-VAR-14)")
      Just (_, area, ty, _) -> do
        when (incomplete at) $ failC "type-mismatch" here "VAR_CONFIG gives a complete address, such as %IX1.0"
        when (locArea at /= area) $ failC "type-mismatch" here (dotted (cfgEntryPath e) <> " is declared at %" <> T.singleton area <> "*, so its address is %" <> T.singleton area <> "..., not " <> locText at <> " (NX-VAR-14)")
        t <- resolveType (cfgEntryType e)
        unless (t == ty) $ failC "type-mismatch" here (dotted (cfgEntryPath e) <> " is a " <> typeText ty <> ", not a " <> typeText t <> " (NX-VAR-14)")
        when (ty == TElem BOOL && locationType at /= TElem BOOL && not (byteSized at)) $ failC "type-mismatch" here ("the address " <> locText at <> " is not a bit")
        pure (area, map StepField path, at, ty)
  forM_ wanted $ \(p, _, _, pos) ->
    unless (any (\(_, s, _, _) -> s == map (StepField . key) p) configured) $
      failC "unconfigured-address" pos ("the instance variable " <> dotted p <> " is declared at an incomplete address and VAR_CONFIG gives it none (NX-VAR-14)")
  pure configured

-- | The programs in the order they run when their tasks are due together:
-- by the task's Number (Tecomat's process, TC-CFG-8), then its PRIORITY
-- (lower first: the IEC task model, TC-CFG-9 and NX-TASK-1 being silent),
-- then the order of association (TC-CFG-11); a program without a task last.
orderedPrograms :: Configuration -> [ProgramConfig]
orderedPrograms c =
  let assoc = [(r, pc) | r <- cfgResources c, pc <- resPrograms r]
      property name r pc = case pcTask pc of
        Nothing -> 2 ^ (62 :: Int) :: Integer
        Just t -> case find ((== key t) . key . taskName) (resTasks r) of
          Just tk -> fromMaybe 0 (lookup name [(key k, n) | (k, ELit _ (LInt n)) <- taskProps tk])
          Nothing -> 0
   in [pc | (_, (_, pc)) <- sortOn (\(i, (r, pc)) -> (property "NUMBER" r pc, property "PRIORITY" r pc, i)) (zip [0 :: Int ..] assoc)]

-- | The INTERVAL of a program's task (in its resource), in milliseconds,
-- when it states one as a TIME literal.
periodOf :: Resource -> ProgramConfig -> Maybe Integer
periodOf r pc = do
  t <- pcTask pc
  tk <- find ((== key t) . key . taskName) (resTasks r)
  ns <- lookup "INTERVAL" [(key k, ns) | (k, ELit _ (LTime ns)) <- taskProps tk]
  pure (ns `div` 1000000)

taskInterval :: Configuration -> Maybe Integer
taskInterval c =
  case [ns | r <- cfgResources c, t <- resTasks r, (k, ELit _ (LTime ns)) <- taskProps t, key k == "INTERVAL"] of
    (ns : _) -> Just (ns `div` 1000000)
    [] -> Nothing

checkDuplicates :: [(Pos, Text)] -> Except VerificationError ()
checkDuplicates = go Set.empty
  where
    go _ [] = pure ()
    go seen ((p, n) : rest)
      | key n `Set.member` seen = throwError (VerificationError "duplicate-identifier" p ("'" <> n <> "' is declared twice in the same scope"))
      | otherwise = go (Set.insert (key n) seen) rest

------------------------------------------------------------------------------
-- Declarations

-- | Tab.2.2 (TC-VAR-9..15): which sections each POU kind may have.
sectionAllowed :: Policies -> PouKind -> Section -> Bool
sectionAllowed pol k s = case (k, s) of
  (_, SecGlobal) -> False
  -- NX-VAR-5, NX-VAR-9, NX-VAR-10: CODESYS's functions have outputs and
  -- VAR_STAT but no VAR_TEMP; programs no VAR_STAT
  (KFunction, SecOutput) -> codesys
  (KFunction, SecTemp) -> not codesys
  (KProgram, SecStat) -> False
  (_, SecStat) -> codesys
  (KFunction, SecExternal) -> False
  _ -> True
  where
    codesys = pExtensions pol == ExtensionsCodesys

-- | The Nexto rules that place a section where 'sectionAllowed' refuses it
-- under CODESYS: globals in a GVL, VAR_TEMP in programs and function blocks,
-- VAR_STAT not in programs. The manual is silent on VAR_EXTERNAL in a
-- function (and CODESYS's functions have outputs), so those cite the IEC
-- core's Tab.2.2 alone.
sectionRules :: Section -> [Text]
sectionRules = \case
  SecGlobal -> ["NX-VAR-7"]
  SecTemp -> ["NX-VAR-9"]
  SecStat -> ["NX-VAR-10"]
  _ -> []

pouVariables :: Pou -> C [VarInfo]
pouVariables p = do
  pol <- asks envPol
  when (pSourceForm pol == MasterToolSource && pouKind p == KFunction) $ do
    -- MT-POU-3: a function has an input; MT-POU-7 (MT-VERR-36): only inputs
    unless (any (\b -> vbSection b == SecInput && not (null (vbDecls b))) (pouVars p)) $
      failC "function-without-input" (pouPos p) ("the function " <> pouName p <> " needs at least one VAR_INPUT parameter (MT-POU-3)")
    forM_ (pouVars p) $ \b -> when (vbSection b `elem` [SecInOut, SecOutput]) $
      failC "function-parameter-kind" (vbPos b) ("the function " <> pouName p <> " may have VAR_INPUT parameters only, not VAR_IN_OUT or VAR_OUTPUT (MT-VERR-36)")
  forM_ (pouVars p) $ \b ->
    unless (sectionAllowed pol (pouKind p) (vbSection b)) $
      failC "section-not-allowed" (vbPos b) (sectionName (vbSection b) <> " is not allowed in a " <> kindName (pouKind p) <> " " <> citing pol ("TC-VAR-9..15" : sectionRules (vbSection b)))
  vs <- concat <$> mapM (blockVars (Just (pouKind p))) (pouVars p)
  let names = [(viPos v, viName v) | v <- vs] ++ [(pouPos p, pouName p) | pouKind p == KFunction]
  either throwError pure (runExcept (checkDuplicates names))
  result <- case (pouKind p, pouResult p) of
    (KFunction, Just t) -> do
      ty <- resolveType t
      pure [VarInfo (pouName p) (key (pouName p)) SecOutput ty (defaultValue ty) False Nothing Nothing (pouPos p) Volatile]
    _ -> pure []
  -- NX-POU-44, NX-POU-45: a derived FB has its base's variables first, and
  -- declares none of their names again
  inherited <- case pouExtends p of
    Nothing -> pure []
    Just (_, b) -> asks (fromMaybe [] . M.lookup (key b) . envVarsOf)
  forM_ vs $ \v -> when (viKey v `elem` map viKey inherited) $
    failC "redeclared-inherited" (viPos v) ("'" <> viName v <> "' is a variable of the base function block already; a derived FB cannot declare it again (NX-POU-45)")
  pure (inherited ++ vs ++ result)

-- | The globals an expression reads, by key.
globalsRead :: CExpr -> [Text]
globalsRead ce = case ceNode ce of
  CRead r -> fromRef r
  CUnary _ a -> globalsRead a
  CBinary _ a b -> globalsRead a ++ globalsRead b
  CConvert _ a -> globalsRead a
  CStandard _ as -> concatMap globalsRead as
  CCall _ ins _ _ -> concatMap (globalsRead . snd) ins
  _ -> []
  where
    fromRef = \case
      CGlobal k -> [k]
      CField r _ -> fromRef r
      CIndex r ixs -> fromRef r ++ concatMap globalsRead ixs
      _ -> []

readMaybeInt :: Text -> Maybe Integer
readMaybeInt t = case reads (T.unpack (T.strip t)) of
  [(n, "")] -> Just n
  _ -> Nothing

-- | CODESYS: each top-level VAR_GLOBAL block is a global list (GVL),
-- named by the attribute gvl_name (docs/nexto.md), qualified_only or not.
-- A variable declared in several lists is stored under LIST.NAME and
-- reached only through its list's name (NX-LEX-8, NX-LEX-9); in lists
-- without a name it is declared twice.
globalLists :: [(VarBlock, [VarInfo])] -> Except VerificationError [(Maybe Text, Bool, [VarInfo])]
globalLists blocks = do
  let named = [(attributeValue "gvl_name" (vbAttributes b), isJust (attributeValue "qualified_only" (vbAttributes b)), vs) | (b, vs) <- blocks]
      counts = M.fromListWith (+) [(viKey v, 1 :: Int) | (_, _, vs) <- named, v <- vs]
      listsOf = M.fromListWith (++) [(viKey v, [n]) | (n, _, vs) <- named, v <- vs]
  forM named $ \(n, qualified, vs) -> do
    vs' <- forM vs $ \v -> case M.findWithDefault 1 (viKey v) counts of
      1 -> pure v
      _
        | Just gvl <- n, all isJust (M.findWithDefault [] (viKey v) listsOf) -> pure v {viKey = key gvl <> "." <> viKey v}
        | otherwise -> throwError (VerificationError "duplicate-identifier" (viPos v) ("'" <> viName v <> "' is declared by several global lists, one of which has no name to tell them apart"))
    pure (n, qualified, vs')

-- | NX-POU-44, NX-POU-47: a function block extends a declared function
-- block, and no chain of EXTENDS comes back to where it started.
checkInheritance :: M.Map Text Pou -> Pou -> Except VerificationError ()
checkInheritance pous p = go [key (pouName p)] (pouExtends p)
  where
    go _ Nothing = pure ()
    go seen (Just (bp, b))
      | key b `elem` seen = throwError (VerificationError "recursive-type" bp ("the function block " <> pouName p <> " extends itself through " <> b))
      | otherwise = case M.lookup (key b) pous of
          Just bpou | pouKind bpou == KFunctionBlock -> go (key b : seen) (pouExtends bpou)
          _ -> throwError (VerificationError "undeclared-type" bp ("the function block " <> b <> " that " <> pouName p <> " extends is not declared"))

-- | The methods, property accessors and actions a POU declares, with their
-- variables (a method's result is a VAR_OUTPUT named like it; a GET's
-- result and a SET's input are named like the property).
memberSignatures :: Pou -> C (M.Map Text (PouKind, [VarInfo]))
memberSignatures p = do
  sigs <- forM (pouMembers p) $ \case
    MMethod m -> do
      vs <- concat <$> mapM (blockVars (Just KMethod)) (mtVars m)
      result <- forM (mtResult m) $ \t -> do
        ty <- resolveType t
        pure (VarInfo (mtName m) (key (mtName m)) SecOutput ty (defaultValue ty) False Nothing Nothing (mtPos m) Volatile)
      let all' = vs ++ maybe [] pure result
      either throwError pure (runExcept (checkDuplicates [(viPos v, viName v) | v <- all']))
      pure [(key (mtName m), (KMethod, all'))]
    MProperty pr -> do
      -- NX-POU-39: a property's accessors have local variables only
      forM_ (maybe [] fst (prGet pr) ++ maybe [] fst (prSet pr)) $ \b ->
        unless (vbSection b `elem` [SecVar, SecTemp]) $
          failC "section-not-allowed" (vbPos b) (sectionName (vbSection b) <> " is not allowed in a property: it has local variables only (NX-POU-39)")
      ty <- resolveType (prType pr)
      let own sec = VarInfo (prName pr) (key (prName pr)) sec ty (defaultValue ty) False Nothing Nothing (prPos pr) Volatile
      getter <- forM (prGet pr) $ \(blocks, _) -> do
        vs <- concat <$> mapM (blockVars (Just KMethod)) blocks
        pure (getterKey (prName pr), (KMethod, vs ++ [own SecOutput]))
      setter <- forM (prSet pr) $ \(blocks, _) -> do
        vs <- concat <$> mapM (blockVars (Just KMethod)) blocks
        pure (setterKey (prName pr), (KMethod, own SecInput : vs))
      pure (maybe [] pure getter ++ maybe [] pure setter)
    MAction _ n _ -> pure [(key n, (KAction, []))]
  let flat = concat sigs
  either throwError pure (runExcept (checkDuplicates [(pos', k) | (k, _) <- flat, let pos' = pouPos p]))
  pure (M.fromList flat)

getterKey, setterKey :: Text -> Text
getterKey n = "GET$" <> key n
setterKey n = "SET$" <> key n

sectionName :: Section -> Text
sectionName = \case
  SecVar -> "VAR"
  SecInput -> "VAR_INPUT"
  SecOutput -> "VAR_OUTPUT"
  SecInOut -> "VAR_IN_OUT"
  SecExternal -> "VAR_EXTERNAL"
  SecGlobal -> "VAR_GLOBAL"
  SecTemp -> "VAR_TEMP"
  SecStat -> "VAR_STAT"

kindName :: PouKind -> Text
kindName = pouKindKeyword

-- | The variables of one block, with their types and initial values.
blockVars :: Maybe PouKind -> VarBlock -> C [VarInfo]
blockVars kind b = do
  -- TC-VAR-19..25 (Tab.3.11): CONSTANT only on VAR and VAR_GLOBAL; RETAIN on
  -- VAR_GLOBAL, and on VAR as the manual's own example shows (TC-ERRATA-10)
  pol <- asks envPol
  let constantSections = [SecVar, SecGlobal] ++ [SecInput | pExtensions pol == ExtensionsCodesys] -- NX-VAR-2
  when (vbConstant b && vbSection b `notElem` constantSections) $
    failC "section-not-allowed" (vbPos b) ("CONSTANT is not allowed on " <> sectionName (vbSection b) <> " (TC-VAR-19..25)")
  -- NX-VAR-1: CODESYS also keeps inputs and outputs of an FB (VAR_INPUT RETAIN)
  let retainSections = [SecVar, SecGlobal] ++ [s | pExtensions pol == ExtensionsCodesys, s <- [SecInput, SecOutput]]
  when (vbRetain b && vbSection b `notElem` retainSections) $
    failC "section-not-allowed" (vbPos b) ("RETAIN is not allowed on " <> sectionName (vbSection b) <> " (TC-VAR-26)")
  when (isNothing kind && vbSection b /= SecGlobal) $
    failC "section-not-allowed" (vbPos b) (sectionName (vbSection b) <> " is only allowed inside a POU")
  -- NX-VAR-20..23, NX-PRAGMA-9: how the block's variables live over resets
  let blockRetention
        | vbPersistent b = Persistent
        | vbRetain b = RetainOverWarm
        | otherwise = Volatile
      retentionOf d
        | any (`elem` ["no_init", "noinit", "no-init"]) (map fst (vdAttributes d ++ vbAttributes b)) = NoInit
        | otherwise = blockRetention
  concat <$> forM (vbDecls b) (\d -> declVars kind (vbSection b) (vbConstant b) (retentionOf d) d)

declVars :: Maybe PouKind -> Section -> Bool -> Retention -> VarDecl -> C [VarInfo]
declVars kind sec constant retention d = do
  pol <- asks envPol
  forM_ (vdNames d) $ \(p, n) -> when (reservedName pol n) (failC "reserved-name" p ("'" <> n <> "' is reserved: " <> reservedWhy pol "variables"))
  ty <- resolveType (vdType d)
  -- MT-POU-6, MT-PARAM-8 (MT-VERR-32): no array is a function's parameter,
  -- no BOOL nor BOOL array a program's
  when (pSourceForm pol == MasterToolSource) $ case (kind, ty) of
    (Just KFunction, TArray {})
      | sec == SecInput -> failC "invalid-parameter-type" (vdPos d) "an array cannot be a parameter of a function (MT-VERR-32)"
    (Just KProgram, t)
      | sec `elem` [SecInput, SecInOut, SecOutput], t == TElem BOOL || isBoolArray t -> failC "invalid-parameter-type" (vdPos d) (typeText t <> " cannot be a parameter of a program (MT-VERR-32)")
    _ -> pure ()
  when (pExtensions pol == ExtensionsCodesys) $ do
    -- NX-POU-10: a function declares no FB instance (an input may take one)
    case ty of
      TFB _ | kind == Just KFunction, sec `elem` [SecVar, SecTemp, SecStat] ->
        failC "instance-in-function" (vdPos d) "a FUNCTION cannot declare a function block instance (NX-POU-10)"
      _ -> pure ()
    -- NX-TYPE-17: BIT only in function blocks and structures
    case vdType d of
      TSName tp n | key n == "BIT", kind /= Just KFunctionBlock ->
        failC "section-not-allowed" tp "a BIT is declared only in a function block or a structure (NX-TYPE-17)"
      _ -> pure ()
    -- NX-TYPE-58: an enumeration is declared with TYPE only
    case vdType d of
      TSEnum tp _ _ | isJust kind -> failC "section-not-allowed" tp "an enumeration is declared with TYPE, not in a POU's variables (NX-TYPE-58)"
      _ -> pure ()
  when (sec == SecExternal && isJust (vdInit d)) $
    failC "external-initialised" (vdPos d) "a VAR_EXTERNAL variable cannot have an initial value (TC-VAR-30)"
  case vdEdge d of
    Just _
      | sec /= SecInput -> failC "section-not-allowed" (vdPos d) "R_EDGE and F_EDGE qualify only inputs (TC-VAR-20)"
      | ty /= TElem BOOL -> failC "type-mismatch" (vdPos d) "R_EDGE and F_EDGE qualify only BOOL inputs (TC-POU-29)"
    _ -> pure ()
  when (isJust (vdAt d) && sec `notElem` [SecVar, SecGlobal]) $
    failC "section-not-allowed" (vdPos d) ("AT is not allowed in " <> sectionName sec)
  -- TC-ADDR-7: the location of symbolic variables only in programs
  when (isJust (vdAt d) && kind `elem` [Just KFunction, Just KFunctionBlock] && not (pExtensions pol == ExtensionsCodesys && kind == Just KFunctionBlock)) $
    failC "section-not-allowed" (vdPos d) "AT gives a location to a variable only in a PROGRAM or among the globals (TC-ADDR-7)"
  -- TC-POU-29: edge inputs belong to function blocks (and programs)
  when (isJust (vdEdge d) && kind == Just KFunction) $
    failC "section-not-allowed" (vdPos d) "R_EDGE and F_EDGE qualify the inputs of function blocks, not of functions (TC-POU-29)"
  -- TC-POU-31: only variables, not FB instances, pass through VAR_IN_OUT
  case ty of
    TFB _ | sec == SecInOut -> failC "section-not-allowed" (vdPos d) "a function block instance cannot be passed through VAR_IN_OUT (TC-POU-31)"
    _ -> pure ()
  -- TC-ADDR-4, TC-ADDR-5: a BOOL lies at a bit address; under CODESYS also
  -- at a byte, word or double word address, of which it fills the first
  -- byte (NX-TYPE-18)
  -- MT-MAP-5, MT-MAP-6, MT-MAP-9, MT-MAP-11, MT-MAP-12 (Table 4-8): the types a
  -- MasterTool operand takes
  case vdAt d of
    Just l | pSourceForm pol == MasterToolSource, not (operandTakes l ty) ->
      failC "incompatible-operand" (vdPos d) ("the PLC operand " <> locText l <> " is incompatible with " <> typeText ty)
    _ -> pure ()
  case (vdAt d, ty) of
    (Just l, TElem BOOL) | pSourceForm pol /= MasterToolSource, locationType l /= TElem BOOL, not (incomplete l), not (pExtensions pol == ExtensionsCodesys && byteSized l) -> failC "type-mismatch" (vdPos d) ("the address " <> locText l <> " is not a bit; a BOOL lies at an address such as %IX0.1 or %X0.1")
    _ -> pure ()
  base <- resolveDefault (vdType d)
  -- NX-VAR-24: under CODESYS an initial value may use variables and calls;
  -- one that is no constant is computed when the controller starts
  -- (checkInits), the type's default standing for it here
  initV <- case vdInit d of
    Nothing -> pure base
    Just i@(IExpr _) | pExtensions pol == ExtensionsCodesys -> initialValue ty base i `catchError` \e ->
      if veKind e `elem` ["not-a-constant", "undeclared-variable", "undeclared-function", "read-not-allowed"] then pure base else throwError e
    Just i -> initialValue ty base i
  -- NX-VAR-14: a variable at %I* or %Q* is an FB's own, placed by VAR_CONFIG
  -- (checkVarConfig) for each instance
  forM_ (vdAt d) $ \l -> when (incomplete l) $ do
    when (kind /= Just KFunctionBlock || sec /= SecVar) $ failC "section-not-allowed" (vdPos d) "an incomplete address (%I*, %Q*) is for the VAR of a function block, which VAR_CONFIG completes (NX-VAR-14)"
    when (null (vdNames d)) $ failC "not-a-variable" (vdPos d) "a variable at an incomplete address needs a name, by which VAR_CONFIG places it (NX-VAR-14)"
  let at = vdAt d >>= \l -> if incomplete l then Nothing else Just l
  case vdNames d of
    [] -> pure [VarInfo (maybe "" locText at) (maybe "" locText at) sec ty initV constant at Nothing (vdPos d) retention]
    ns -> pure [VarInfo n (key n) sec ty initV constant at (vdEdge d) p retention | (p, n) <- ns]

isBoolArray :: Type -> Bool
isBoolArray = \case
  TArray _ (TElem BOOL) -> True
  _ -> False

-- | The initial value of a type as declared: a TYPE's own initial value,
-- the initial values of a structure's fields, the type's default otherwise
-- (TC-TYPE-21..23); an FB instance holds its variables' initial values.
resolveDefault :: TypeSpec -> C Value
resolveDefault spec = do
  ty <- resolveType spec
  pol <- asks envPol
  case spec of
    -- policy subrange-initial (TC-TYPE-21, NX-TYPE-35)
    _ | TSubrange e lo hi <- ty, pSubrangeInitial pol == SubrangeZero, lo <= 0, 0 <= hi, not (isNamed spec) -> pure (VInt e 0)
    TSName _ n | Nothing <- parseElemName n -> do
      types <- asks envTypes
      depth <- asks envTypeDepth
      case M.lookup (key n) types of
        Just td -> local (\e -> e {envTypeDepth = depth + 1}) $ do
          base <- case ty of
            TEnum {} -> pure (defaultValue ty) -- the value carries the type's name
            TNumEnum {} -> pure (defaultValue ty)
            _ -> resolveDefault (tdSpec td)
          maybe (pure base) (initialValue ty base) (tdInit td)
        Nothing -> case ty of
          TFB fb -> instanceValue fb
          _ -> pure (defaultValue ty)
    TSExtends p b own -> do
      baseValue <- resolveDefault (TSName p b)
      ownValue <- resolveDefault own
      pure $ case (baseValue, ownValue) of
        (VStruct m1, VStruct m2) -> VStruct (M.union m2 m1)
        _ -> ownValue
    TSStruct _ ds -> do
      fields <- forM ds $ \d -> do
        ft <- resolveType (vdType d)
        fb <- resolveDefault (vdType d)
        v <- maybe (pure fb) (initialValue ft fb) (vdInit d)
        pure [(key n, v) | (_, n) <- vdNames d]
      pure (VStruct (M.fromList (concat fields)))
    TSArray _ _ t -> do
      e <- resolveDefault t
      pure $ case defaultValue ty of
        VArray bs xs -> VArray bs (fmap (const e) xs)
        v -> v
    _ -> pure (defaultValue ty)

-- | NX-TYPE-74: @POINTER TO T@. A structure or union that a TYPE declares
-- is named, not spelt out ('TNamed'), so that its members may point at it.
pointerTo :: TypeSpec -> C Type
pointerTo spec = do
  types <- asks envTypes
  case spec of
    TSName _ n
      | Just td <- M.lookup (key n) types, structured (tdSpec td) -> pure (TPointer (TNamed (tdName td)))
      -- an alias of a name: the pointer names what the alias names
      | Just td <- M.lookup (key n) types, TSName {} <- tdSpec td -> do
          depth <- asks envTypeDepth
          when (depth > 64) (failC "recursive-type" (tdPos td) ("the type " <> n <> " is defined through itself"))
          local (\e -> e {envTypeDepth = depth + 1}) (pointerTo (tdSpec td))
    _ -> pointerOf <$> resolveType spec
  where
    structured = \case
      TSStruct {} -> True
      TSUnion {} -> True
      TSExtends {} -> True
      _ -> False

-- | The type of a pointer to a value of this type (ADR, NX-TYPE-75).
pointerOf :: Type -> Type
pointerOf = \case
  TStruct n _ | not (T.null n) -> TPointer (TNamed n)
  TUnion n _ | not (T.null n) -> TPointer (TNamed n)
  t -> TPointer t

-- | What a pointer points at, a named structure looked up.
pointee :: Pos -> Type -> C Type
pointee p = \case
  TNamed n -> resolveType (TSName p n)
  t -> pure t

-- | A type given by name (whose TYPE may state its own initial value).
isNamed :: TypeSpec -> Bool
isNamed = \case
  TSName {} -> True
  _ -> False

instanceValue :: Text -> C Value
instanceValue n = do
  std <- asks envStd
  varsOf <- asks envVarsOf
  depth <- asks envTypeDepth
  when (depth > 32) (failC "recursive-type" (Pos 1 1) ("the function block " <> n <> " contains itself"))
  case M.lookup (key n) std of
    Just d -> pure (VInstance (pdName d) (M.fromList [(viKey v, viInit v) | v <- pdVars d]))
    Nothing -> case M.lookup (key n) varsOf of
      Just vs -> pure (VInstance n (M.fromList [(viKey v, viInit v) | v <- vs]))
      Nothing -> pure (VInstance n M.empty)

-- | A type as written, resolved: aliases are replaced by what they name
-- (TC-TYPE-34, TC-TYPE-35).
resolveType :: TypeSpec -> C Type
resolveType = \case
  TSName p n -> case parseElemName n of
    Just e -> do
      -- MT-TYPE-1: MasterTool has eight of the elementary types
      mt <- masterToolSource
      when (mt && e `notElem` elementaryTypes) $
        failC "unsupported-type" p ("the type " <> n <> " is not a type of MasterTool XE (BOOL, BYTE, WORD, DWORD, USINT, INT, DINT, REAL; MT-TYPE-1)")
      pure (TElem e)
    Nothing | key n == "BIT" -> do
      -- NX-TYPE-17: CODESYS's BIT holds TRUE or FALSE, a BOOL to the program
      pol <- asks envPol
      if pExtensions pol == ExtensionsCodesys then pure (TElem BOOL) else failC "undeclared-type" p "the type BIT is not declared"
    Nothing -> do
      types <- asks envTypes
      pous <- asks envPous
      std <- asks envStd
      depth <- asks envTypeDepth
      when (depth > 64) (failC "recursive-type" p ("the type " <> n <> " is defined through itself"))
      case M.lookup (key n) types of
        Just td -> do
          t <- local (\e -> e {envTypeDepth = depth + 1}) (resolveType (tdSpec td))
          pure (case t of
            TEnum "" vs -> TEnum (tdName td) vs
            TNumEnum "" e vs -> TNumEnum (tdName td) e vs
            TStruct "" fs -> TStruct (tdName td) fs
            TUnion "" fs -> TUnion (tdName td) fs
            _ -> t)
        Nothing
          | Just pd <- M.lookup (key n) pous, pouKind pd == KFunctionBlock -> pure (TFB (pouName pd))
          | Just d <- M.lookup (key n) std -> pure (TFB (pdName d))
          | otherwise -> failC "undeclared-type" p ("the type " <> n <> " is not declared")
  TSString p wide len -> do
    pol <- asks envPol
    n <- case len of
      Nothing -> pure (pStringLength pol) -- TC-TYPE-26
      Just e -> fromInteger <$> constInt e
    when (n < 1) (failC "value-out-of-limits" p "a string's length must be at least 1")
    pure (TString wide (fromInteger (toInteger n)))
  TSArray p dims t -> do
    pol <- asks envPol
    let most = pArrayDimensions pol
    when (length dims > most) (failC "too-many-dimensions" p ("an array has at most " <> T.pack (show most) <> " dimensions " <> citing pol ["TC-TYPE-39", "NX-TYPE-42"]))
    mt <- masterToolSource
    bs <- forM dims $ \(a, b) -> do
      lo <- constInt a
      hi <- constInt b
      -- MT-ARR-4 (MT-VERR-37, MT-VERR-38) and MT-VERR-44: MasterTool's
      -- bounds run from 0 upwards, at most 65536 elements
      when mt $ do
        when (lo < 0) (failC "value-out-of-limits" (exprPos a) ("the lower bound " <> T.pack (show lo) <> " of an array cannot be negative (MT-ARR-4)"))
        when (hi < lo) (failC "min-greater-than-max" (exprPos a) ("the array bounds " <> T.pack (show lo) <> ".." <> T.pack (show hi) <> " have the minimum above the maximum (MT-ARR-4)"))
        when (hi - lo + 1 > 65536) (failC "invalid-array-size" (exprPos a) "an array has at most 65536 elements (MT-VERR-44)")
      when (hi < lo) (failC "value-out-of-limits" (exprPos a) "the upper bound of an array is below its lower bound")
      when (not mt && (lo < -32768 || hi > 32767)) (failC "value-out-of-limits" (exprPos a) "array bounds lie within the range of INT (TC-TYPE-40)")
      pure (lo, hi)
    TArray bs <$> resolveType t
  TSStruct _ ds -> do
    forM_ ds $ \d -> when (isJust (vdAt d)) $
      failC "section-not-allowed" (vdPos d) "a structure's member has no address (NX-TYPE-51)"
    fs <- forM ds $ \d -> do
      t <- resolveType (vdType d)
      pure [(n, t) | (_, n) <- vdNames d]
    pure (TStruct "" (concat fs))
  -- NX-TYPE-72: a union's members share their storage, so each is plain
  -- data with no initial value of its own
  TSUnion p ds -> do
    fs <- forM ds $ \d -> do
      when (isJust (vdAt d) || isJust (vdInit d)) $
        failC "section-not-allowed" (vdPos d) "a union's member has no address and no initial value of its own: its members share their bytes (NX-TYPE-72)"
      t <- resolveType (vdType d)
      unless (plainData t) $
        failC "type-mismatch" (vdPos d) ("a union's member is data: " <> typeText t <> " cannot share its storage (NX-TYPE-72)")
      pure [(n, t) | (_, n) <- vdNames d]
    when (null (concat fs)) (failC "type-mismatch" p "a union declares at least one member")
    pure (TUnion "" (concat fs))
  TSEnum p items base -> do
    pol <- asks envPol
    case pEnumerations pol of
      EnumSymbolic -> do
        forM_ [e | (_, _, Just e) <- items] $ \e -> failC "type-mismatch" (exprPos e) "an enumerated value has no number under enumerations = symbolic (TC-TYPE-21)"
        when (isJust base) (failC "type-mismatch" p "an enumeration has no base type under enumerations = symbolic")
        pure (TEnum "" [n | (_, n, _) <- items])
      EnumInteger -> do
        -- NX-TYPE-62, NX-TYPE-66: numbered from 0, or on from a value given;
        -- INT unless a base type is given; every value fits it (NX-TYPE-67)
        e <- case base of
          Nothing -> pure INT
          Just b -> case parseElemName b of
            Just e | isInt e -> pure e
            _ -> failC "type-mismatch" p ("the base type of an enumeration is an integer type, not " <> b)
        let go _ [] = pure []
            go next ((vp, n, v) : rest) = do
              x <- maybe (pure next) constInt v
              unless (fitInt e x) (failC "value-out-of-limits" vp ("the value " <> T.pack (show x) <> " of " <> n <> " lies outside " <> elemName e <> " (NX-TYPE-67)"))
              ((n, x) :) <$> go (x + 1) rest
        TNumEnum "" e <$> go 0 items
  TSPointer _ t -> pointerTo t
  TSExtends p b spec -> do
    -- NX-TYPE-55: the base structure's members first, none declared again
    base <- resolveType (TSName p b)
    own <- resolveType spec
    case (base, own) of
      (TStruct _ bfs, TStruct _ ofs) -> do
        let at f = case spec of
              TSStruct _ ds | (fp : _) <- [np | d <- ds, (np, n) <- vdNames d, key n == key f] -> fp
              _ -> p
        forM_ ofs $ \(f, _) -> when (key f `elem` map (key . fst) bfs) $
          failC "redeclared-inherited" (at f) ("the member " <> f <> " is a member of " <> b <> " already (NX-TYPE-55)")
        pure (TStruct "" (bfs ++ ofs))
      _ -> failC "type-mismatch" p "a structure extends a structure (NX-TYPE-55)"
  TSSubrange p n (a, b) -> do
    base <- resolveType (TSName p n)
    lo <- constInt a
    hi <- constInt b
    pol <- asks envPol
    case base of
      TElem e | isAnyInt e -> pure (TSubrange e lo hi)
      -- NX-TYPE-68: CODESYS also ranges BYTE, WORD, DWORD, LWORD
      TElem e | isBitString e, pExtensions pol == ExtensionsCodesys -> pure (TSubrange e lo hi)
      _ -> failC "type-mismatch" p ("a subrange is a range of an integer type " <> citing pol ["TC-TYPE-32", "NX-TYPE-68"])

-- | A constant integer (array bounds, string lengths, subranges).
constInt :: Expr -> C Integer
constInt e = do
  v <- constValue Nothing e
  case v of
    VInt _ n -> pure n
    _ -> failC "not-a-constant" (exprPos e) "an integer constant was expected"

-- | The value of a constant expression: literals, enumerated values,
-- CONSTANT globals and operators over them.
constValue :: Maybe Type -> Expr -> C Value
constValue expected e = do
  ce <- checkExprAt expected e
  -- TC-TYPE-23, TC-CONV-1: an initial value has the variable's type
  ce' <- maybe (pure ce) (`assignable` ce) expected
  evalConst ce'

evalConst :: CExpr -> C Value
evalConst ce = do
  pol <- asks envPol
  globals <- asks envGlobals
  let go c = case ceNode c of
        CConst v -> Right v
        CUnary o a -> go a >>= either (Left . faultMessage) Right . unary pol o
        CBinary o a b -> do
          x <- go a
          y <- go b
          either (Left . faultMessage) Right (binary pol o x y)
        CConvert t a -> go a >>= either (Left . faultMessage) Right . convert pol (ceType a) t
        CRead (CGlobal k) | Just v <- M.lookup k globals, viConstant v -> Right (viInit v)
        _ -> Left "this is not a constant expression"
  either (failC "not-a-constant" (cePos ce)) pure (go ce)

-- | An initial value of a type (TC-TYPE-23, TC-TYPE-43, TC-TYPE-44), over
-- the type's own initial value (what a list leaves out keeps it).
initialValue :: Type -> Value -> Init -> C Value
initialValue ty base = \case
  IExpr e -> constValue (Just ty) e >>= \v -> fitStore (exprPos e) ty v
  IArray p items -> case ty of
    TArray bs t -> do
      let elemBase = case base of
            VArray _ xs | Just x <- Seq.lookup 0 xs -> x
            _ -> defaultValue t
      let size = fromInteger (product [hi - lo + 1 | (lo, hi) <- bs]) :: Int
      -- MT-ARR-7 (MT-VERR-30): a MasterTool list gives every element
      mt <- masterToolSource
      when (mt && length items /= size) $
        failC "wrong-initializer-count" p ("the array has " <> T.pack (show size) <> " elements but the list gives " <> T.pack (show (length items)) <> " values (MT-VERR-30)")
      vals <- concat <$> forM items (\(rep, i) -> do
        n <- maybe (pure 1) constInt rep
        -- TC-TYPE-43: a repetition fits the array, checked before it is built
        when (n < 0 || n > toInteger size) (failC "value-out-of-limits" p ("a repetition count of " <> T.pack (show n) <> " for an array of " <> T.pack (show size) <> " elements"))
        v <- case i of
          IArray _ [] -> pure elemBase
          _ -> initialValue t elemBase i
        pure (replicate (fromInteger n) v))
      when (length vals > size) (failC "value-out-of-limits" p "more initial values than array elements")
      pure (VArray bs (Seq.fromList (vals ++ replicate (size - length vals) elemBase)))
    _ -> failC "type-mismatch" p ("a list of initial values for " <> typeText ty <> ", which is not an array")
  IStruct p fields -> case (ty, base) of
    (TStruct _ fs, VStruct m) -> do
      vals <- forM fields $ \(f, i) -> case lookup (key f) [(key n, t) | (n, t) <- fs] of
        Nothing -> failC "undeclared-variable" p ("the structure has no field " <> f)
        Just t -> (key f,) <$> initialValue t (M.findWithDefault (defaultValue t) (key f) m) i
      pure (VStruct (M.union (M.fromList vals) m))
    _ -> failC "type-mismatch" p ("a structure's initial values for " <> typeText ty)

-- | A constant that must fit its declared type.
fitStore :: Pos -> Type -> Value -> C Value
fitStore p ty v = case (ty, v) of
  (TSubrange _ lo hi, VInt e n)
    | n < lo || n > hi -> failC "value-out-of-limits" p ("the value " <> T.pack (show n) <> " lies outside the subrange " <> T.pack (show lo) <> ".." <> T.pack (show hi))
    | otherwise -> pure (VInt e n)
  -- TC-TYPE-27: a string cut to its capacity (policy string-overflow)
  (TString _ cap, VString str)
    | T.length str > cap -> do
        pol <- asks envPol
        case pStringOverflow pol of
          StringTruncate -> pure (VString (T.take cap str))
          StringOverflowError -> failC "value-out-of-limits" p ("the initial string has " <> T.pack (show (T.length str)) <> " characters; the variable holds " <> T.pack (show cap))
  _ -> pure v

------------------------------------------------------------------------------
-- POU bodies

checkPou :: Pou -> C PouDef
checkPou p = do
  locals <- asks envLocals
  pol <- asks envPol
  globals <- asks envGlobals
  -- NX-VAR-13, NX-ERR-32: VAR_EXTERNAL repeats a global's declaration exactly
  when (pExtensions pol == ExtensionsCodesys) $
    forM_ [v | v <- M.elems locals, viSection v == SecExternal] $ \v -> case M.lookup (viKey v) globals of
      Just g | viType g == viType v -> pure ()
      Just g -> failC "external-mismatch" (viPos v) ("VAR_EXTERNAL " <> viName v <> " is a " <> typeText (viType v) <> "; the global is a " <> typeText (viType g) <> " (NX-VAR-13)")
      Nothing -> failC "external-mismatch" (viPos v) ("VAR_EXTERNAL " <> viName v <> " names no global variable (NX-VAR-13, NX-ERR-32)")
  -- MT-POU-3, MT-POU-12: a MasterTool FUNCTION or PROGRAM has a statement
  -- (a lone ; will do)
  when (pSourceForm pol == MasterToolSource && null (pouBody p) && pouKind p `elem` [KFunction, KProgram]) $
    failC "missing-statement" (pouPos p) "a FUNCTION or PROGRAM needs at least one statement; a lone ; will do (MT-POU-12)"
  body <- checkStmts (pouBody p)
  -- MT-POU-4 (MT-VERR-18): every path through a MasterTool function
  -- assigns its result
  when (pSourceForm pol == MasterToolSource && pouKind p == KFunction) $ case missingResult (key (pouName p)) (pouBody p) of
    Just at -> failC "missing-return-value" (fromMaybe (pouPos p) at) ("a path through the function " <> pouName p <> " ends without assigning its result (MT-VERR-18)")
    Nothing -> pure ()
  members <- checkMembers p
  inits <- checkInits [(b, d) | b <- pouVars p, d <- vbDecls b]
  initArgs <- checkInitArgs [d | b <- pouVars p, d <- vbDecls b]
  let vars = M.elems locals
      ordered = sortOn viPos vars
  pure
    PouDef
      { pdKind = pouKind p
      , pdName = pouName p
      , pdVars = ordered
      , pdVarMap = locals
      , pdResult = (\k -> viType <$> M.lookup k locals) (key (pouName p)) >>= \t -> if pouKind p == KFunction then Just t else Nothing
      , pdBody = Statements body
      , pdEndPos = pouEnd p
      , pdBase = key . snd <$> pouExtends p
      , pdInits = inits
      , pdInitArgs = initArgs
      , pdChecked = key (pouName p) `notElem` checkFunctionNames && isNothing (attributeValue "no_check" (pouAttributes p)) -- NX-PRAGMA-8
      , pdMethods = members
      }

-- | MT-POU-4: a path through a function's body that ends without assigning
-- the result: Just the RETURN that leaves so, or Just Nothing for the end
-- of the body; Nothing when every path assigns it. WHILE and FOR may run
-- zero times, REPEAT runs once at least, EXIT leaves its loop.
missingResult :: Text -> [Stmt] -> Maybe (Maybe Pos)
missingResult result body = case flowList False body of
  (_, _, p : _) -> Just (Just p)
  (Just False, _, []) -> Just Nothing
  _ -> Nothing
  where
    -- (assigned when falling through, assigned at the EXITs, the RETURNs
    -- reached unassigned); Nothing where no path falls through
    flowList d = \case
      [] -> (Just d, Nothing, [])
      s : ss -> case flowStmt d s of
        (Nothing, x, bad) -> (Nothing, x, bad)
        (Just d', x, bad) -> let (n2, x2, bad2) = flowList d' ss in (n2, joinM x x2, bad ++ bad2)
    flowStmt d = \case
      SAssign _ (EVar _ n) _ | key n == result -> (Just True, Nothing, [])
      SReturn p -> (Nothing, Nothing, [p | not d])
      SExit _ -> (Nothing, Just d, [])
      SIf _ arms els -> joinAll (map (flowList d . snd) arms ++ [flowList d els])
      SCase _ _ arms els -> joinAll (map (flowList d . snd) arms ++ [flowList d els])
      SWhile _ _ b -> let (_, _, bad) = flowList d b in (Just d, Nothing, bad)
      SFor _ _ _ _ _ b -> let (_, _, bad) = flowList d b in (Just d, Nothing, bad)
      SRepeat _ b _ -> let (n, x, bad) = flowList d b in (joinM n x, Nothing, bad)
      _ -> (Just d, Nothing, [])
    joinM (Just a) (Just b) = Just (a && b)
    joinM Nothing b = b
    joinM a Nothing = a
    joinAll rs = (foldr (joinM . (\(n, _, _) -> n)) Nothing rs, foldr (joinM . (\(_, x, _) -> x)) Nothing rs, concatMap (\(_, _, b) -> b) rs)

-- | NX-VAR-24, NX-VAR-25: the initial values that are no constants,
-- checked as expressions of the scope, in declaration order.
checkInits :: [(VarBlock, VarDecl)] -> C [(Text, Type, CExpr)]
checkInits decls = do
  pol <- asks envPol
  if pExtensions pol /= ExtensionsCodesys
    then pure []
    else fmap concat . forM decls $ \(_, d) -> case vdInit d of
      Just (IExpr e) -> do
        ty <- resolveType (vdType d)
        isConst <- (True <$ constValue (Just ty) e) `catchError` const (pure False)
        if isConst
          then pure []
          else do
            ce <- checkExprAt (Just ty) e >>= assignable ty
            pure [(key n, ty, ce) | (_, n) <- vdNames d]
      _ -> pure []

-- | NX-POU-35: the inputs given to an FB instance at its declaration,
-- @com1 : Dev(nCom := 1)@, which its FB_Init method receives: by instance
-- key, each input checked against the FB_Init of the FB or of the nearest
-- FB it extends.
checkInitArgs :: [VarDecl] -> C (M.Map Text [(Text, CExpr)])
checkInitArgs decls = fmap (M.fromList . concat) . forM [d | d <- decls, not (null (vdArgs d))] $ \d -> do
  ty <- resolveType (vdType d)
  inputs <- case ty of
    TFB fb -> fromMaybe [] <$> fbInitInputs fb
    _ -> failC "type-mismatch" (vdPos d) "inputs in parentheses after the type are given only to a function block instance's FB_Init (NX-POU-35)"
  args <- forM (vdArgs d) $ \case
    ArgInput p n e -> case find (\v -> viKey v == key n && viSection v == SecInput) inputs of
      Just v -> (viKey v,) <$> (checkExprAt (Just (viType v)) e >>= assignable (viType v))
      Nothing -> failC "unknown-parameter" p ("the FB_Init of " <> typeText ty <> " has no input " <> n <> " (NX-POU-35)")
    ArgPositional e -> failC "unknown-parameter" (exprPos e) "an FB_Init input at a declaration is given by name, e.g. (nCom := 1) (NX-POU-35)"
    ArgOutput p _ _ -> failC "unknown-parameter" p "an FB_Init has no outputs to bind at a declaration (NX-POU-35)"
  pure [(key n, args) | (_, n) <- vdNames d]

-- | The variables of the FB_Init an FB declares or inherits, if any.
fbInitInputs :: Text -> C (Maybe [VarInfo])
fbInitInputs = go (16 :: Int) . key
  where
    go 0 _ = pure Nothing
    go n k = do
      own <- asks (M.lookup k . envMembersOf)
      case own >>= M.lookup "FB_INIT" of
        Just (_, vs) -> pure (Just vs)
        Nothing -> do
          base <- asks (\e -> M.lookup k (envPous e) >>= pouExtends)
          maybe (pure Nothing) (go (n - 1) . key . snd) base

-- | The bodies of a POU's methods, accessors and actions. A method runs in
-- a frame of its own and reaches its instance's variables (but not its
-- VAR_IN_OUT and VAR_TEMP: NX-POU-29); an action runs on the instance's
-- variables as the body does (NX-POU-41).
checkMembers :: Pou -> C (M.Map Text PouDef)
checkMembers p = do
  sigs <- asks (fromMaybe M.empty . M.lookup (key (pouName p)) . envMembersOf)
  instanceVars <- asks envLocals
  let visible = M.filter (\v -> viSection v `notElem` [SecInOut, SecTemp]) instanceVars
      method k name' end' blocksBody = case M.lookup k sigs of
        Nothing -> pure []
        Just (kind, vars) -> do
          let varMap = M.fromList [(viKey v, v) | v <- vars]
          body <- local (\e -> e {envLocals = varMap, envInstanceVars = visible, envLoop = False, envLabels = Set.empty, envStatic = "$STAT." <> key (pouName p) <> "." <> k <> "."}) (checkStmts blocksBody)
          pure
            [ ( k
              , PouDef
                  { pdKind = kind
                  , pdName = name'
                  , pdVars = vars
                  , pdVarMap = varMap
                  , pdResult = viType <$> find (\v -> viSection v == SecOutput && viKey v == resultKey k) vars
                  , pdBody = Statements body
                  , pdEndPos = end'
                  , pdBase = Nothing
                  , pdInits = []
                  , pdInitArgs = M.empty
                  , pdChecked = True
                  , pdMethods = M.empty
                  }
              )
            ]
      resultKey k = maybe k id (T.stripPrefix "GET$" k)
  defs <- forM (pouMembers p) $ \case
    MMethod m -> method (key (mtName m)) (mtName m) (mtPos m) (mtBody m)
    MProperty pr -> do
      g <- maybe (pure []) (method (getterKey (prName pr)) (prName pr) (prPos pr) . snd) (prGet pr)
      st <- maybe (pure []) (method (setterKey (prName pr)) (prName pr) (prPos pr) . snd) (prSet pr)
      pure (g ++ st)
    MAction ap n stmts -> do
      body <- local (\e -> e {envLoop = False, envLabels = Set.empty}) (checkStmts stmts)
      pure [(key n, PouDef KAction n [] M.empty Nothing (Statements body) ap Nothing [] M.empty True M.empty)]
  pure (M.fromList (concat defs))

checkStmts :: [Stmt] -> C [CStmt]
checkStmts ss = do
  let labels = [(p, n) | SLabel p n <- ss]
  either throwError pure (runExcept (checkDuplicates labels))
  -- MT-STMT-22, MT-VERR-16: under MasterTool a statement after RETURN or
  -- EXIT in the same list is an error (the empty statement aside)
  mt <- masterToolSource
  let statements = filter (\case SEmpty _ -> False; _ -> True) ss
      jumps = \case
        SReturn _ -> True
        SExit _ -> True
        _ -> False
  case [s | (j, s) <- zip statements (drop 1 statements), jumps j] of
    s : _ | mt -> failC "unreachable-code" (stmtPos s) "this statement can never run: it follows a RETURN or EXIT in the same statement list (MT-VERR-16)"
    _ -> pure ()
  local (\e -> e {envLabels = envLabels e `Set.union` Set.fromList (map (key . snd) labels)}) (catMaybes <$> mapM checkStmt ss)

checkStmt :: Stmt -> C (Maybe CStmt)
checkStmt = \case
  SEmpty _ -> pure Nothing
  SAssign p target value
    | isMemberPath target -> do
        prop <- propertyAccess setterKey target
        case prop of
          Just (ref, d, ty, n) -> do
            -- NX-POU-38: writing a property calls its SET
            v <- checkExprAt (Just ty) value >>= assignable ty
            pure (Just (CEval p (CExpr p (TElem BOOL) (CMethod d ref [(n, v)] [] []))))
          Nothing -> plainAssign p target value
  SAssign p target value -> plainAssign p target value
  SCall p callee args -> Just <$> checkCallStmt p callee args
  SIf p arms els -> do
    arms' <- forM arms $ \(c, b) -> (,) <$> condition c <*> checkStmts b
    Just . CIf p arms' <$> checkStmts els
  SCase p sel arms els -> do
    s <- checkExprAt Nothing sel 
    case ceType s of
      TElem e | isAnyInt e -> pure ()
      TSubrange {} -> pure ()
      TEnum {} -> pure ()
      TNumEnum {} -> pure ()
      t -> failC "type-mismatch" (exprPos sel) ("a CASE selector is an integer or an enumeration, not " <> typeText t <> " (TC-STMT-11, TC-STMT-16)")
    arms' <- forM arms $ \(labels, b) -> do
      ranges <- forM labels $ \case
        CaseValue e -> (\o -> (o, o)) <$> labelOrdinal (ceType s) e
        CaseRange a b' -> (,) <$> labelOrdinal (ceType s) a <*> labelOrdinal (ceType s) b'
      (ranges,) <$> checkStmts b
    mt <- masterToolSource
    when mt $ masterToolLabels [(labelPos l, r) | ((labels, _), (ranges, _)) <- zip arms arms', (l, r) <- zip labels ranges]
    Just . CCase p s arms' <$> checkStmts els
  SFor p v start end step body -> do
    mt <- masterToolSource
    when mt $ masterToolFor p v
    (ref, ty) <- checkTarget (EVar p v)
    case baseElem ty of
      Just e | isAnyInt e -> pure ()
      _ -> failC "type-mismatch" p ("the FOR control variable " <> v <> " must be of an integer type (TC-STMT-19)")
    s <- checkExprAt (Just ty) start >>= assignable ty
    e <- checkExprAt (Just ty) end >>= assignable ty
    st <- traverse (\x -> checkExprAt (Just ty) x >>= assignable ty) step
    b <- local (\env -> env {envLoop = True, envForVars = [key v | mt] ++ envForVars env}) (checkStmts body)
    pure (Just (CFor p ref ty s e st b))
  SWhile p c body -> do
    c' <- condition c
    Just . CWhile p c' <$> local (\env -> env {envLoop = True}) (checkStmts body)
  SRepeat p body c -> do
    b <- local (\env -> env {envLoop = True}) (checkStmts body)
    Just . CRepeat p b <$> condition c
  SExit p -> do
    inLoop <- asks envLoop
    pol <- asks envPol
    unless inLoop (failC "exit-outside-loop" p ("EXIT stands outside a FOR, WHILE or REPEAT loop " <> citing pol ["TC-STMT-36", "NX-STMT-38"]))
    pure (Just (CExit p))
  SReturn p -> pure (Just (CReturn p))
  SContinue p -> do
    inLoop <- asks envLoop
    unless inLoop (failC "continue-outside-loop" p "CONTINUE stands outside a FOR, WHILE or REPEAT loop (NX-STMT-35)")
    pure (Just (CContinue p))
  SLabel p n -> pure (Just (CLabel p (key n)))
  SJump p n -> do
    labels <- asks envLabels
    unless (key n `Set.member` labels) (failC "undeclared-label" p ("JMP to " <> n <> ", which labels no statement of this block or of an enclosing one (NX-STMT-42)"))
    pure (Just (CJump p (key n)))
  SChain p targets value -> do
    -- NX-STMT-6..9: the value reaches the rightmost target first; after an
    -- assignment the next target takes what was stored, after S= or R=
    -- the value itself
    (_, lastType) <- checkTarget (fst (last targets))
    v <- checkExprAt (Just lastType) value
    let go _ [] acc = pure acc
        go cur ((t, op) : rest) acc = do
          (ref, ty) <- checkTarget t
          case op of
            OpAssign -> do
              _ <- assignable ty cur
              let from = if sameType ty (ceType cur) then Nothing else Just (ceType cur)
              go (CExpr (exprPos t) ty (CRead ref)) rest ((op, ref, ty, from) : acc)
            _ -> do
              unless (ceType cur == TElem BOOL && ty == TElem BOOL) $
                failC "type-mismatch" (exprPos t) "S= and R= set or reset a BOOL by a BOOL (NX-STMT-7, NX-STMT-8)"
              go cur rest ((op, ref, ty, Nothing) : acc)
    Just . CChain p v <$> go v (reverse targets) []

-- | MT-STMT-10, MT-STMT-11 (MT-VERR-27, MT-VERR-38): under MasterTool a
-- CASE's ranges run upwards, and no value labels two cases; each label with
-- its position and its range, in the order written.
masterToolLabels :: [(Pos, (Integer, Integer))] -> C ()
masterToolLabels = go []
  where
    go _ [] = pure ()
    go seen ((p, (a, b)) : rest)
      | a > b = failC "min-greater-than-max" p ("the range " <> T.pack (show a) <> ".." <> T.pack (show b) <> " has its minimum above its maximum (MT-VERR-38)")
      | used@(_ : _) <- [max a c | (c, d) <- seen, c <= b, a <= d] = failC "case-value-duplicated" p ("the value " <> T.pack (show (minimum used)) <> " is already used by another case of this CASE (MT-VERR-27)")
      | otherwise = go ((a, b) : seen) rest

-- | Decision A22: MasterTool uses an array element by element only.
wholeArray :: Pos -> Text -> C a
wholeArray p n = failC "whole-array-use" p ("the array " <> n <> " is used element by element, e.g. " <> n <> "[i] (decision A22)")

-- | The position of a CASE label (its first value).
labelPos :: CaseLabel -> Pos
labelPos = \case
  CaseValue e -> exprPos e
  CaseRange a _ -> exprPos a

-- | MasterTool's rules for a FOR's control variable, before the core's:
-- not the control variable of an enclosing FOR (MT-STMT-20, MT-VERR-29),
-- not mapped to a PLC operand (MT-STMT-17, MT-VERR-28), USINT or INT
-- (MT-STMT-16).
masterToolFor :: Pos -> Text -> C ()
masterToolFor p v = do
  fors <- asks envForVars
  when (key v `elem` fors) $ failC "for-variable-written" p ("the FOR control variable " <> v <> " cannot be written inside its FOR (MT-VERR-29)")
  found <- lookupName p v
  case found of
    Just (CLocated {}, _, _) -> failC "for-variable-mapped" p ("the FOR control variable " <> v <> " is mapped to a PLC operand (MT-VERR-28)")
    Just (_, ty, _) | ty `notElem` [TElem USINT, TElem INT] -> failC "invalid-for-variable" p ("the FOR control variable " <> v <> " must be USINT or INT (MT-STMT-16)")
    _ -> pure ()

-- | An assignment to a variable.
plainAssign :: Pos -> Expr -> Expr -> C (Maybe CStmt)
plainAssign p target value = do
  -- MT-STMT-20, MT-VERR-29: a FOR's control variable is not written in its
  -- body; A22: nor a MasterTool array as a whole
  fors <- asks envForVars
  mt <- masterToolSource
  case target of
    EVar tp n | key n `elem` fors -> failC "for-variable-written" tp ("the FOR control variable " <> n <> " cannot be written inside its FOR (MT-VERR-29)")
    EVar tp n | mt -> lookupName tp n >>= \case
      Just (_, TArray {}, _) -> wholeArray tp n
      _ -> pure ()
    _ -> pure ()
  (ref, ty) <- checkTarget target
  v <- checkExprAt (Just ty) value >>= assignable ty
  pol <- asks envPol
  when (pExtensions pol == ExtensionsCodesys) $ case (ty, ceNode v) of
    -- NX-TYPE-70, NX-ERR-28: a constant outside a subrange is a compile error
    (TSubrange _ lo hi, CConst (VInt _ n))
      | n < lo || n > hi -> failC "value-out-of-limits" (exprPos value) ("the constant " <> T.pack (show n) <> " lies outside the subrange " <> T.pack (show lo) <> ".." <> T.pack (show hi) <> " (NX-TYPE-70)")
    _ -> pure ()
  pure (Just (CAssign p ref ty v))

-- | Could the expression name a property: @x.f@, or a bare name?
isMemberPath :: Expr -> Bool
isMemberPath = \case
  EField {} -> True
  EVar {} -> True
  _ -> False

condition :: Expr -> C CExpr
condition c = do
  ce <- checkExprAt (Just (TElem BOOL)) c 
  unless (ceType ce == TElem BOOL) (failC "type-mismatch" (exprPos c) ("a condition must be BOOL, not " <> typeText (ceType ce) <> " (TC-STMT-10)"))
  pure ce

-- | A CASE label's ordinal: the integer, or the enumerated value's position.
labelOrdinal :: Type -> Expr -> C Integer
labelOrdinal t e = do
  v <- constValue (Just t) e
  case (v, t) of
    (VInt _ n, _) -> pure n
    (VEnum _ n, TEnum _ vs) | Just i <- lookup (key n) (zip (map key vs) [0 ..]) -> pure i
    _ -> failC "type-mismatch" (exprPos e) ("this CASE label does not have the selector's type " <> typeText t)

-- | The target of an assignment, with the write rules: a VAR_INPUT inside its
-- POU (TC-VAR-1), a CONSTANT (TC-VAR-18), an FB's output from outside
-- (TC-POU-24) cannot be written.
checkTarget :: Expr -> C (CRef, Type)
checkTarget target = do
  (ref, ty, access) <- checkRef target
  pol <- asks envPol
  -- NX-VAR-19, NX-ERR-31: the program does not write an input's image
  case ref of
    CLocated l _ | locArea l `elem` ['I', 'X'], pExtensions pol == ExtensionsCodesys ->
      failC "write-not-allowed" (exprPos target) ("the variable at " <> locText l <> " is an input: the program cannot write it (NX-VAR-19)")
    _ -> pure ()
  case access of
    Writable -> pure (ref, ty)
    ReadOnly why -> failC "write-not-allowed" (exprPos target) why
    Hidden why -> failC "write-not-allowed" (exprPos target) why
    WriteOnly _ -> pure (ref, ty)

data Access = Writable | ReadOnly Text | Hidden Text | WriteOnly Text -- ^ MasterTool's outputs (MT-VERR-25)

-- | A variable reference with its type and what may be done with it.
checkRef :: Expr -> C (CRef, Type, Access)
checkRef = \case
  EVar p n -> do
    r <- lookupName p n
    case r of
      Just x -> pure x
      Nothing -> listedGlobal p n >> failC "undeclared-variable" p ("the variable " <> n <> " is not declared")
  ELocated lp loc -> do
    -- MT-MAP-2: a MasterTool module reaches an operand through a variable
    -- mapped with AT only; its grammar has no operand in the code
    mt <- masterToolSource
    when mt $ failC "expected-token" lp ("the operand " <> locText loc <> " is reached through a variable declared AT it (MT-MAP-2)")
    pure (CLocated loc (locationType loc), locationType loc, Writable)
  EField p (EVar gp g) f -> do
    -- NX-OP-89, NX-VAR-35: a global list's name before its variable
    isVar <- isJust <$> lookupName gp g
    gvl <- asks (M.lookup (key g) . envGvls)
    case gvl of
      Just vs | not isVar -> case M.lookup (key f) vs of
        Just v -> pure (maybe (CGlobal (viKey v)) (\l -> CLocated l (viType v)) (viAt v), viType v, if viConstant v then ReadOnly ("the CONSTANT " <> viName v <> " cannot be written") else Writable)
        Nothing -> failC "undeclared-variable" p ("the global list " <> g <> " has no variable " <> f)
      _ -> fieldOf p (EVar gp g) f
  EField p base f -> fieldOf p base f
  EIndex p base ixs -> do
    (ref, ty, access) <- checkRef base
    case ty of
      TArray bs t -> do
        when (length ixs /= length bs) (failC "type-mismatch" p ("the array has " <> T.pack (show (length bs)) <> " dimensions, not " <> T.pack (show (length ixs))))
        is <- forM ixs $ \i -> do
          ce <- checkExprAt (Just (TElem DINT)) i 
          case baseElem (ceType ce) of
            Just e | isAnyInt e -> pure ce
            _ -> failC "type-mismatch" (exprPos i) "an array index is an integer (TC-TYPE-38)"
        pure (CIndex ref is, t, access)
      TPointer target | [i] <- ixs -> do
        -- NX-TYPE-77: p[i] is (p + i * SIZEOF(T))^, the i-th element from p
        ce <- checkExprAt (Just (TElem DINT)) i
        t <- pointee p target
        step <- pointerStep t
        let asDWord c = CExpr (cePos c) (TElem DWORD) (CConvert (TElem DWORD) c)
            base' = CExpr p (TElem DWORD) (CRead ref)
            offset = CExpr p (TElem DWORD) (CBinary BMul (asDWord ce) (CExpr p (TElem DWORD) (CConst (VInt DWORD step))))
        pure (CDeref (CExpr p (TPointer target) (CBinary BAdd base' offset)) t, t, Writable)
      TString w _ | [i] <- ixs -> do
        -- NX-TYPE-77: a STRING's character as a BYTE, a WSTRING's as a WORD, from 0
        ce <- checkExprAt (Just (TElem DINT)) i
        pure (CCharAt w ref ce, TElem (if w then WORD else BYTE), access)
      _ -> failC "type-mismatch" p (typeText ty <> " is not an array")
  EBit p base i -> bitOf p base i
  EDeref p (EThis _) -> do
    -- NX-POU-28: THIS^ is the instance the code runs on
    self <- asks envSelf
    case self of
      Just t -> (\ty -> (CThis, ty, Writable)) <$> selfType p t
      Nothing -> failC "not-a-variable" p "THIS is the instance of a function block; it is used inside one"
  EDeref p (ESuper _) -> do
    (_, b) <- superOf p
    pure (CThis, TFB b, Writable)
  EDeref p e -> do
    -- NX-TYPE-75: p^ is what p points at
    ce <- checkExprAt Nothing e
    case ceType ce of
      TPointer target -> pointee p target >>= \t -> pure (CDeref ce t, t, Writable)
      t -> failC "type-mismatch" p ("^ follows a pointer; this is a " <> typeText t)
  EGlobalScope p n -> do
    -- NX-OP-88, NX-VAR-34: .name is the global, whatever a local is called
    globals <- asks envGlobals
    case M.lookup (key n) globals of
      Just g -> pure (maybe (CGlobal (key n)) (\l -> CLocated l (viType g)) (viAt g), viType g, if viConstant g then ReadOnly ("the CONSTANT " <> viName g <> " cannot be written") else Writable)
      Nothing -> failC "undeclared-variable" p ("there is no global variable " <> n)
  e -> failC "not-a-variable" (exprPos e) "a variable was expected here"

-- | A name no scope declares may still be a global that must be written
-- with its list's name: say so (NX-PRAGMA-10, NX-LEX-9).
listedGlobal :: Pos -> Text -> C ()
listedGlobal p n = do
  qualifiedOnly <- asks (Set.member (key n) . envQualifiedOnly)
  ambiguous <- asks (Set.member (key n) . envAmbiguous)
  when qualifiedOnly $ failC "qualified-only" p ("the global list of " <> n <> " is qualified_only: write its name before the variable, GVL." <> n <> " (NX-PRAGMA-10)")
  when ambiguous $ failC "ambiguous-name" p ("several global lists declare " <> n <> "; write the list's name before it (NX-LEX-9)")

-- | NX-OP-92..96: bit i of an integer variable, a BOOL; the types SINT,
-- INT, DINT, USINT, UINT, UDINT, BYTE, WORD, DWORD; i below the width.
bitOf :: Pos -> Expr -> Integer -> C (CRef, Type, Access)
bitOf p base i = do
  (ref, ty, access) <- checkRef base
  case baseElem ty of
    Just e
      | e `elem` [SINT, INT, DINT, USINT, UINT, UDINT, BYTE, WORD, DWORD] -> do
          when (i < 0 || i >= toInteger (intBits e)) $
            failC "bit-index-out-of-range" p ("the index " <> T.pack (show i) <> " lies outside the bits 0.." <> T.pack (show (intBits e - 1)) <> " of " <> typeText ty <> " (NX-OP-95)")
          pure (CBit ref (fromInteger i), TElem BOOL, access)
    _ -> failC "invalid-bit-access" p ("a bit is taken of SINT, INT, DINT, USINT, UINT, UDINT, BYTE, WORD or DWORD, not of " <> typeText ty <> " (NX-OP-94, NX-OP-96)")

-- | A field of a structure or a variable of an FB instance, with the
-- access rules (TC-POU-23..25).
fieldOf :: Pos -> Expr -> Text -> C (CRef, Type, Access)
fieldOf p base f = do
  (ref, ty, access) <- checkRef base
  pol <- asks envPol
  constant <- if pExtensions pol == ExtensionsCodesys then namedConstant f else pure Nothing
  case ty of
    _ | Just i <- constant, Just _ <- baseElem ty -> bitOf p base i -- NX-OP-92: the index may be a named constant
    TStruct _ fs -> case lookup (key f) [(key n, t) | (n, t) <- fs] of
      Just t -> pure (CField ref (key f), t, access)
      Nothing -> failC "undeclared-variable" p ("the structure " <> typeText ty <> " has no field " <> f)
    TUnion _ fs -> case lookup (key f) [(key n, t) | (n, t) <- fs] of
      Just t -> pure (CField ref (key f), t, access)
      Nothing -> failC "undeclared-variable" p ("the union " <> typeText ty <> " has no member " <> f)
    _ | Just fb <- instanceType ty -> do
      d <- fbVars fb
      case find ((== key f) . viKey) d of
        Nothing -> failC "undeclared-variable" p ("the function block " <> fb <> " has no variable " <> f)
        Just v | own base -> pure (CField ref (key f), viType v, Writable) -- NX-POU-28: THIS^.x
        Just v -> case viSection v of
          SecInput -> pure (CField ref (key f), viType v, access) -- TC-POU-25
          SecOutput -> do
            pol <- asks envPol
            pure (CField ref (key f), viType v, case pFBAccess pol of
              AccessIec -> ReadOnly ("the output " <> f <> " of a function block instance is written only by the instance (TC-POU-24)")
              AccessCodesys -> access) -- NX-POU-19
          _ -> pure (CField ref (key f), viType v, Hidden ("the variable " <> f <> " is internal to the function block " <> fb <> " " <> citing pol ["TC-POU-23", "NX-POU-19"]))
    _ -> failC "type-mismatch" p (typeText ty <> " has no fields")
  where
    instanceType = \case
      TFB fb -> Just fb
      TProgram prg -> Just prg
      _ -> Nothing
    own = \case
      EDeref _ (EThis _) -> True
      EDeref _ (ESuper _) -> True
      _ -> False

-- | The value of a named integer constant (a local or global CONSTANT).
namedConstant :: Text -> C (Maybe Integer)
namedConstant n = do
  locals <- asks envLocals
  globals <- asks envGlobals
  pure $ case M.lookup (key n) locals <|> M.lookup (key n) globals of
    Just v | viConstant v, VInt _ i <- viInit v -> Just i
    _ -> Nothing

-- | The type of the instance a POU's code runs on.
selfType :: Pos -> Text -> C Type
selfType p t = do
  pous <- asks envPous
  case M.lookup t pous of
    Just pou | pouKind pou == KProgram -> pure (TProgram (pouName pou))
    Just pou -> pure (TFB (pouName pou))
    Nothing -> failC "not-a-variable" p "THIS is the instance of a function block"

-- | NX-POU-46: SUPER^ is the running instance seen as its base FB.
superOf :: Pos -> C (Text, Text)
superOf p = do
  self <- asks envSelf
  pous <- asks envPous
  case self >>= (`M.lookup` pous) of
    Just pou | Just (_, b) <- pouExtends pou -> pure (key (pouName pou), b)
    _ -> failC "not-a-variable" p "SUPER^ names the base of a function block that EXTENDS another"

------------------------------------------------------------------------------
-- Methods, properties and actions (CODESYS: NX-POU-25..47)

-- | A method, accessor or action of a POU type, its own or inherited: its
-- kind and variables.
memberOf :: Text -> Text -> C (Maybe (PouKind, [VarInfo]))
memberOf t m = go (16 :: Int) (key t)
  where
    go 0 _ = pure Nothing
    go n k = do
      members <- asks envMembersOf
      pous <- asks envPous
      case M.lookup k members >>= M.lookup (key m) of
        Just sig -> pure (Just sig)
        Nothing -> case M.lookup k pous >>= pouExtends of
          Just (_, b) -> go (n - 1) (key b)
          Nothing -> pure Nothing

-- | The instance and type a call or property access names: @inst.m@,
-- @THIS^.m@, @p^.m@, @SUPER^.m@ (static), or a bare @m@ of the running
-- instance. Nothing when the callee is not a member.
memberTarget :: Expr -> C (Maybe (CRef, Text, Text, Bool))
memberTarget = \case
  EField p (EDeref _ (ESuper _)) m -> do
    (_, b) <- superOf p
    pure (Just (CThis, b, m, False))
  EField _ base m -> do
    r <- (Just <$> checkRef base) `catchError` const (pure Nothing)
    case r of
      Just (ref, TFB t, _) -> pure (Just (ref, t, m, True))
      Just (ref, TProgram t, _) -> pure (Just (ref, t, m, True))
      _ -> pure Nothing
  EVar p m -> do
    self <- asks envSelf
    found <- lookupName p m
    case (self, found) of
      (Just t, Nothing) -> pure (Just (CThis, t, m, True))
      _ -> pure Nothing
  _ -> pure Nothing

-- | A call of a method or action (NX-POU-30, NX-POU-42), Nothing when the
-- callee names none. A method binds its own parameters; an action the
-- inputs of its POU. The value is the method's result.
memberCall :: Pos -> Expr -> [Arg] -> C (Maybe CExpr)
memberCall p callee args = do
  target <- memberTarget callee
  case target of
    Nothing -> pure Nothing
    Just (ref, t, m, virtual) -> do
      sig <- memberOf t m
      case sig of
        Nothing -> pure Nothing
        Just (kind, vars) -> do
          params <- if kind == KAction then fbVars t else pure vars
          (ins, inouts, outs) <- bindArgs p m params args
          let result = maybe (TElem BOOL) viType (find (\v -> viKey v == key m && viSection v == SecOutput) vars)
              dispatch = if virtual then Virtual (key m) else Static (key t) (key m)
          pure (Just (CExpr p result (CMethod dispatch ref ins inouts outs)))

-- | A property of an instance (NX-POU-37, NX-POU-38): where the instance is
-- and the property's type, when the expression names one with that accessor.
propertyAccess :: (Text -> Text) -> Expr -> C (Maybe (CRef, Dispatch, Type, Text))
propertyAccess accessor e = do
  target <- case e of
    EField {} -> memberTarget e
    EVar {} -> memberTarget e
    _ -> pure Nothing
  case target of
    Nothing -> pure Nothing
    Just (ref, t, n, virtual) -> do
      isVar <- any ((== key n) . viKey) <$> fbVars t
      sig <- if isVar then pure Nothing else memberOf t (accessor n)
      pure $ case sig of
        Just (_, vars) | Just v <- find ((== key n) . viKey) vars ->
          Just (ref, if virtual then Virtual (accessor n) else Static (key t) (accessor n), viType v, key n)
        _ -> Nothing

-- | The size of a pointer's base type: the step of @p[i]@.
pointerStep :: Type -> C Integer
pointerStep t = do
  varsOf <- asks envVarsOf
  std <- asks envStd
  packs <- asks envPackModes
  pol <- asks envPol
  let membersOf n = [(viKey v, viType v) | v <- maybe (M.findWithDefault [] (key n) varsOf) pdVars (M.lookup (key n) std), isNothing (viAt v)]
  pure (sizeInBytes (layout membersOf (`M.lookup` packs) (pTimeRange pol)) t)

fbVars :: Text -> C [VarInfo]
fbVars fb = do
  std <- asks envStd
  varsOf <- asks envVarsOf
  pure (maybe (fromMaybe [] (M.lookup (key fb) varsOf)) pdVars (M.lookup (key fb) std))

-- | A name in a body: the function's result, a local or a global (policy
-- @name-resolution@, TC-VAR-33), with the access rules.
lookupName :: Pos -> Text -> C (Maybe (CRef, Type, Access))
lookupName _ n = do
  pol <- asks envPol
  static <- asks envStatic
  locals <- asks envLocals
  instanceVars <- asks envInstanceVars
  globals <- asks envGlobals
  pou <- asks envPou
  let k = key n
      asLocal v = case viSection v of
        SecExternal -> asGlobalNamed v
        SecStat -> Just (CGlobal (static <> k), viType v, localAccess v) -- NX-VAR-10: one copy per POU
        _ -> Just (refOf (CLocal k) v, viType v, localAccess v)
      asGlobalNamed v = case M.lookup (viKey v) globals of
        Just g -> Just (refOf (CGlobal (viKey g)) g, viType g, globalAccess g)
        Nothing -> Nothing
      asGlobal g = (refOf (CGlobal (viKey g)) g, viType g, globalAccess g)
      refOf r v = maybe r (\l -> CLocated l (viType v)) (viAt v)
      mt = pSourceForm pol == MasterToolSource
      localAccess v
        -- MT-VERR-25: a PROGRAM's VAR_OUTPUT is written, not read
        | mt, viSection v == SecOutput, fmap pouKind pou == Just KProgram = WriteOnly ("the output " <> viName v <> " is written by the program and cannot be read (MT-VERR-25)")
        | viSection v == SecInput && pFBAccess pol == AccessIec = ReadOnly ("the input " <> viName v <> " is read-only inside its own POU (TC-VAR-1)")
        | viConstant v = ReadOnly ("the CONSTANT " <> viName v <> " cannot be written " <> citing pol ["TC-VAR-18", "NX-VAR-16"])
        | otherwise = Writable
      globalAccess g
        -- MT-SIG-2, MT-OP-7 (MT-VERR-25, MT-VERR-26): the controller's signals
        | mt, Just ReadSignal <- signalUse (viKey g) = ReadOnly (viName g <> " is read-only (MT-VERR-26)")
        | mt, Just WriteSignal <- signalUse (viKey g) = WriteOnly (viName g <> " is write-only (MT-VERR-25)")
        | viConstant g = ReadOnly ("the CONSTANT " <> viName g <> " cannot be written " <> citing pol ["TC-VAR-18", "NX-VAR-16"])
        | otherwise = Writable
      loc = M.lookup k locals >>= asLocal
      inst = (\v -> (CInstance k, viType v, globalAccess v)) <$> M.lookup k instanceVars
      -- decision A20: the signals are seen in the PROGRAM only
      glob = asGlobal <$> M.lookup k (if mt && fmap pouKind pou == Just KFunction then M.filterWithKey (\gk _ -> isNothing (signalUse gk)) globals else globals)
  programInstance <- asks (M.lookup k . envProgramInstance)
  -- NX-POU-3, NX-POU-4: a program's name is its instance, read (PRG.out)
  -- and called from other programs and function blocks
  let prog = case (programInstance, pProgramCalls pol, fmap pouKind pou) of
        (Just i, ProgramCallsAllowed, Just kind) | kind /= KFunction -> Just (CProgram i, TProgram n, Writable)
        _ -> Nothing
  pure $ (<|> prog) $ case pNameResolution pol of
    LocalWins -> maybe (maybe glob Just inst) Just loc
    GlobalWins -> maybe (maybe inst Just loc) Just glob

------------------------------------------------------------------------------
-- Expressions

-- | A checked expression and, for an untyped literal, its exact value: it
-- takes the type of its context (TC-CONV-4).
data Flex = Fixed | FlexInt Integer | FlexReal Rational

type TExpr = (CExpr, Flex)

-- | Check an expression; the expected type, when known, types untyped
-- literals.
checkExprAt :: Maybe Type -> Expr -> C CExpr
checkExprAt expected e = do
  te <- infer expected e
  case expected of
    Just t | isFlex te -> coerceLit t te >>= maybe (settle te) pure
    _ -> settle te

isFlex :: TExpr -> Bool
isFlex (_, f) = case f of
  Fixed -> False
  _ -> True

-- | An untyped literal without context: DINT (or LINT beyond its range) and
-- LREAL.
settle :: TExpr -> C CExpr
settle (ce, f) = case f of
  Fixed -> pure ce
  FlexInt n -> pure ce {ceType = TElem (if fitInt DINT n then DINT else LINT), ceNode = CConst (VInt (if fitInt DINT n then DINT else LINT) n)}
  FlexReal r -> pure ce {ceType = TElem LREAL, ceNode = CConst (VLReal (fromRational r))}

-- | An untyped literal given a type, if the literal can have it; a literal
-- outside the type's range is @value-out-of-limits@.
coerceLit :: Type -> TExpr -> C (Maybe CExpr)
coerceLit t (ce, f) = do
  mt <- masterToolSource
  case (f, baseElem t) of
    -- MT-CONST-2 (Table 4-15): MasterTool's BOOL literals are also 0 and 1
    (FlexInt n, Just BOOL) | mt -> do
      unless (n == 0 || n == 1) (failC "value-out-of-limits" (cePos ce) ("the literal " <> T.pack (show n) <> " is not a BOOL: 0, 1, FALSE or TRUE (MT-CONST-2)"))
      pure (Just (lit BOOL (VBool (n == 1))))
    -- MT-CONST-2, decision A10: an integer literal is a REAL through the
    -- implicit INT to REAL, so only within INT's range
    (FlexInt n, Just REAL) | mt, not (fitInt INT n) -> failC "value-out-of-limits" (cePos ce) ("the literal " <> T.pack (show n) <> " lies outside INT's range, the integers a REAL takes (MT-CONST-2)")
    _ -> coerceIec t (ce, f)
  where
    lit e v = ce {ceType = TElem e, ceNode = CConst v}

-- | 'coerceLit' by the IEC rules.
coerceIec :: Type -> TExpr -> C (Maybe CExpr)
coerceIec t (ce, f) = case (f, baseElem t) of
  (FlexInt n, Just e)
    | isInt e -> do
        unless (fitInt e n) (failC "value-out-of-limits" (cePos ce) ("the literal " <> T.pack (show n) <> " lies outside the range of " <> elemName e))
        pure (Just (lit e (VInt e n)))
    | e == REAL -> pure (Just (lit e (VReal (fromInteger n))))
    | e == LREAL -> pure (Just (lit e (VLReal (fromInteger n))))
  (FlexReal r, Just e)
    | e == REAL -> pure (Just (lit e (VReal (fromRational r))))
    | e == LREAL -> pure (Just (lit e (VLReal (fromRational r))))
  _ -> pure Nothing
  where
    lit e v = ce {ceType = maybe (TElem e) (const t) (subr t), ceNode = CConst v}
    subr = \case
      TSubrange {} -> Just ()
      _ -> Nothing

-- | The value of an expression in a context of the given type: the same
-- type, or an implicit conversion the policy allows (TC-CONV-1, TC-CONV-3).
assignable :: Type -> CExpr -> C CExpr
assignable t ce
  | sameType t (ceType ce) = pure ce
  | Just ce' <- pointerAssignable t ce = pure ce'
  | otherwise = do
      pol <- asks envPol
      case (baseElem (ceType ce), baseElem t) of
        (Just from, Just to) | implicitAllowed (pImplicitConversions pol) from to -> pure (CExpr (cePos ce) t (CConvert t ce))
        -- arrays are one type only with the same bounds and elements: no
        -- conversion joins two others
        _ | TArray {} <- t, TArray {} <- ceType ce -> failC "type-mismatch" (cePos ce) ("a value of type " <> typeText (ceType ce) <> " where " <> typeText t <> " is expected: arrays of other bounds or elements are other types " <> citing pol ["TC-TYPE-38", "NX-TYPE-43"])
        _ -> failC "type-mismatch" (cePos ce) ("a value of type " <> typeText (ceType ce) <> " where " <> typeText t <> " is expected; convert it explicitly " <> citing pol ["TC-CONV-1", "TC-CONV-3", "NX-CONV-1", "NX-CONV-2"])

-- | NX-TYPE-75, NX-TYPE-78: an address is a DWORD: any pointer, or a
-- DWORD, may be stored in a pointer, and a pointer in a DWORD.
pointerAssignable :: Type -> CExpr -> Maybe CExpr
pointerAssignable t ce = case (t, ceType ce) of
  (TPointer _, TPointer _) -> Just ce {ceType = t}
  (TPointer _, TElem e) | e `elem` [DWORD, UDINT] -> Just ce {ceType = t}
  -- the null pointer written as 0, or another integer constant
  (TPointer _, TElem e) | isInt e, CConst _ <- ceNode ce -> Just (CExpr (cePos ce) t (CConvert (TElem DWORD) ce))
  (TElem DWORD, TPointer _) -> Just ce {ceType = t}
  (TElem e, TPointer _) | isInt e, intBits e >= 32 -> Just (CExpr (cePos ce) t (CConvert t ce {ceType = TElem DWORD}))
  _ -> Nothing

-- | Implicit widening conversions of the policy's alternatives.
implicitAllowed :: ImplicitConversions -> Elem -> Elem -> Bool
implicitAllowed ic from to = case ic of
  ImplicitNone -> False
  ImplicitCodesys -> (from, to) `elem` widening || codesys
  -- MT-CONV-6 (A9): MasterTool's seven edges; USINT to REAL is explicit
  ImplicitMastertool -> (from, to) `elem` widening && (from, to) /= (USINT, REAL)
  ImplicitIecWidening -> (from, to) `elem` widening
  where
    -- NX-CONV-1..8: never to a narrower integer; the manual's own CTUD
    -- example stores a WORD in an INT (NX-CONV-7), so signedness and bit
    -- string/integer may change at equal width; every integer becomes a
    -- REAL or LREAL (NX-CONV-3)
    codesys =
      (isInt from && isInt to && intBits to >= intBits from)
        || (isInt from && isAnyReal to)
    chain xs = [(a, b) | (i, a) <- zip [0 :: Int ..] xs, (j, b) <- zip [0 ..] xs, i < j]
    widening =
      chain [SINT, INT, DINT, LINT] ++ chain [USINT, UINT, UDINT, ULINT] ++ chain [BYTE, WORD, DWORD, LWORD]
        ++ [(USINT, INT), (USINT, DINT), (USINT, LINT), (UINT, DINT), (UINT, LINT), (UDINT, LINT), (REAL, LREAL)]
        ++ [(a, REAL) | a <- [SINT, INT, USINT, UINT]] ++ [(a, LREAL) | a <- [SINT, INT, DINT, USINT, UINT, UDINT]]

infer :: Maybe Type -> Expr -> C TExpr
infer expected = \case
  ELit p l -> literal p l
  EEnum p t v -> do
    ty <- resolveType (TSName p t)
    case ty of
      TEnum _ vs | Just v' <- find ((== key v) . key) vs -> fixed p ty (CConst (VEnum (enumName ty) v'))
      TNumEnum _ e vs | Just (_, x) <- find ((== key v) . key . fst) vs -> fixed p ty (CConst (VInt e x))
      TNumEnum {} -> failC "undeclared-variable" p ("the enumeration " <> t <> " has no value " <> v)
      TEnum {} -> failC "undeclared-variable" p ("the enumeration " <> t <> " has no value " <> v)
      _ -> failC "type-mismatch" p (t <> " is not an enumeration")
  EVar p n -> do
    r <- lookupName p n
    mt <- masterToolSource
    case r of
      Just (_, _, Hidden why) -> failC "read-not-allowed" p why
      Just (_, _, WriteOnly why) -> failC "read-not-allowed" p why
      Just (_, TArray {}, _) | mt -> wholeArray p n
      Just (ref, ty, _) -> fixed p ty (CRead ref)
      Nothing -> do
        prop <- propertyAccess getterKey (EVar p n)
        case prop of
          Just (ref, d, ty, _) -> fixed p ty (CMethod d ref [] [] [])
          Nothing -> listedGlobal p n >> enumValue p n expected
  EField p (EVar tp t) v
    | otherwise -> do
        -- NX-TYPE-65, NX-OP-91: an enumeration's name before its value
        isVar <- isJust <$> lookupName tp t
        types <- asks envTypes
        if not isVar && M.member (key t) types
          then do
            ty <- resolveType (TSName tp t)
            case ty of
              TNumEnum {} -> infer expected (EEnum p t v)
              TEnum {} -> infer expected (EEnum p t v)
              _ -> fieldRead
          else fieldRead
    where
      fieldRead = do
        let e = EField p (EVar tp t) v
        prop <- propertyAccess getterKey e
        case prop of
          Just (ref, d, ty, _) -> fixed p ty (CMethod d ref [] [] [])
          Nothing -> readRef e
  e@(EField p _ _) -> do
    prop <- propertyAccess getterKey e
    case prop of
      Just (ref, d, ty, _) -> fixed p ty (CMethod d ref [] [] [])
      Nothing -> readRef e
  e@EDeref {} -> readRef e
  e@EBit {} -> readRef e
  e@EGlobalScope {} -> readRef e
  EInvoke p callee args -> do
    r <- memberCall p callee args
    case r of
      Just ce -> pure (ce, Fixed)
      Nothing -> failC "not-a-function-block" p "this names no method of a function block"
  ECall p f args -> do
    -- NX-POU-50: inside a method its name is its result; called, it would recurse
    self <- asks envSelf
    locals <- asks envLocals
    own <- maybe (pure Nothing) (`memberOf` f) self
    case (own, M.lookup (key f) locals) of
      (Just (KMethod, _), Just v) | viSection v == SecOutput -> failC "recursive-call" p ("the method " <> f <> " calls itself; recursion is not allowed (NX-POU-50)")
      _ -> pure ()
    r <- isUserFunction f >>= \isF -> if isF then pure Nothing else memberCall p (EVar p f) args
    maybe (callExpr expected p f args) (\ce -> pure (ce, Fixed)) r
  e@EIndex {} -> readRef e
  e@ELocated {} -> readRef e
  EUn p UNeg (ELit _ (LInt n)) -> pure (CExpr p (TElem DINT) (CConst (VInt DINT (negate n))), FlexInt (negate n)) -- TC-LEX-27
  EUn p UNeg (ELit _ (LReal r _)) -> pure (CExpr p (TElem LREAL) (CConst (VLReal (fromRational (negate r)))), FlexReal (negate r))
  EUn p o a -> do
    ca <- checkExprAt expected a
    t <- either (failC "invalid-unary-operation" p) pure (unaryType o (ceType ca))
    fixed p t (CUnary o ca)
  EBin p o a b -> binaryExpr expected p o a b
  EThis p -> failC "not-a-variable" p "THIS is a pointer; THIS^ is the instance"
  ESuper p -> failC "not-a-variable" p "SUPER is a pointer; SUPER^ is the base instance"

-- | Is the name a FUNCTION of the unit, a standard function or a conversion?
isUserFunction :: Text -> C Bool
isUserFunction f = do
  pous <- asks envPous
  pol <- asks envPol
  pure $ case M.lookup (key f) pous of
    Just pou -> pouKind pou == KFunction
    Nothing -> key f `elem` standardFunctionNames || isJust (conversionName pol (key f)) || isJust (libraryFunction pol (key f))

fixed :: Pos -> Type -> CNode -> C TExpr
fixed p t n = pure (CExpr p t n, Fixed)

enumName :: Type -> Text
enumName = \case
  TEnum n _ -> n
  _ -> ""

readRef :: Expr -> C TExpr
readRef e = do
  (ref, ty, access) <- checkRef e
  case access of
    Hidden why -> failC "read-not-allowed" (exprPos e) why
    WriteOnly why -> failC "read-not-allowed" (exprPos e) why
    _ -> fixed (exprPos e) ty (CRead ref)

-- | An unqualified enumerated value (TC-TYPE-36): the expected type's, or the
-- only declared enumeration that has it.
enumValue :: Pos -> Text -> Maybe Type -> C TExpr
enumValue p n expected = do
  types <- asks envTypes
  locals <- asks envLocals
  globals <- asks envGlobals
  named <- forM (M.elems types) (\td -> resolveType (TSName (tdPos td) (tdName td)))
  let anonymous = [viType v | v <- M.elems locals ++ M.elems globals] >>= enumsIn
      candidates = [t | t <- maybe [] enumsIn expected ++ concatMap enumsIn named ++ anonymous, key n `elem` map key (valuesOf t)]
  case candidates of
    (t@(TNumEnum _ e vs) : rest)
      -- NX-TYPE-59, NX-TYPE-65: known everywhere; unqualified only where one enumeration has it
      | all (== t) rest, Just (_, x) <- find ((== key n) . key . fst) vs -> fixed p t (CConst (VInt e x))
      | otherwise -> failC "ambiguous-name" p ("the value " <> n <> " belongs to several enumerations; write it as Type." <> n <> " (NX-TYPE-65)")
    (t@(TEnum _ vs) : rest)
      | all (== t) rest || maybe False (`elem` enumsInM expected) (Just t) ->
          fixed p t (CConst (VEnum (enumName t) (fromMaybe n (find ((== key n) . key) vs))))
      | otherwise -> failC "ambiguous-name" p ("the value " <> n <> " belongs to several enumerations; write it as Type#" <> n)
    _ -> failC "undeclared-variable" p ("the variable " <> n <> " is not declared")
  where
    valuesOf = \case
      TEnum _ vs -> vs
      TNumEnum _ _ vs -> map fst vs
      _ -> []
    enumsIn = \case
      t@TEnum {} -> [t]
      t@TNumEnum {} -> [t]
      TArray _ t -> enumsIn t
      TStruct _ fs -> concatMap (enumsIn . snd) fs
      TUnion _ fs -> concatMap (enumsIn . snd) fs
      _ -> []
    enumsInM = maybe [] enumsIn

literal :: Pos -> Literal -> C TExpr
literal p = \case
  LInt n -> pure (CExpr p (TElem DINT) (CConst (VInt DINT n)), FlexInt n)
  LBits n -> literal p (LInt n)
  LReal r _ -> pure (CExpr p (TElem LREAL) (CConst (VLReal (fromRational r))), FlexReal r)
  LBool b -> fixed p (TElem BOOL) (CConst (VBool b))
  LString s -> fixed p (TString False (max 1 (T.length s))) (CConst (VString s))
  LWString s -> fixed p (TString True (max 1 (T.length s))) (CConst (VString s))
  LTime ns -> do
    let ms = ns `quot` 1000000
    pol <- asks envPol
    unless (fitsUnder pol TIME ms) (failC "value-out-of-limits" p (if pTimeRange pol == TimeUnsigned then "the duration lies outside the range of TIME, 0 to T#49d17h2m47s295ms (NX-TYPE-30)" else "the duration lies outside the range of TIME (TC-TYPE-19)"))
    fixed p (TElem TIME) (CConst (VTime TIME ms))
  LDate ns -> fixed p (TElem DATE) (CConst (VDate (ns `div` 1000000)))
  LTod ns -> fixed p (TElem TOD) (CConst (VTod (ns `div` 1000000)))
  LDT ns -> fixed p (TElem DT) (CConst (VDT (ns `div` 1000000)))
  LTyped t l -> do
    ty <- resolveType (TSName p t)
    codesysLiterals <- asks ((== ExtensionsCodesys) . pExtensions . envPol)
    case (baseElem ty, l) of -- TC-LEX-24
      (Just BOOL, LInt n) | n == 0 || n == 1 -> fixed p ty (CConst (VBool (n == 1)))
      (Just BOOL, LBool b) -> fixed p ty (CConst (VBool b))
      (Just LTIME, LTime ns) -> do
        unless (fitInt LTIME ns) (failC "value-out-of-limits" p "the duration lies outside the range of LTIME (NX-TYPE-33)")
        fixed p ty (CConst (VTime LTIME ns))
      -- NX-LEX-33: under CODESYS a typed literal of a signed type beyond its
      -- range but within its width is a bit pattern, DINT#16#FFFFFFFF = -1
      (Just e, LBits n)
        | isSignedInt e, codesysLiterals, n > snd (intRange e), n < 2 ^ intBits e ->
            fixed p ty (CConst (VInt e (n - 2 ^ intBits e)))
      (_, LBits n) -> typed ty (LInt n)
      (_, LInt _) -> typed ty l
      (_, LReal _ _) -> typed ty l
      (_, LString s) | TString {} <- ty -> fixed p ty (CConst (VString s))
      _ -> failC "type-mismatch" p ("the literal cannot have the type " <> t)
  where
    typed ty l = do
      te <- literal p l
      r <- coerceLit ty te
      maybe (failC "type-mismatch" p ("the literal cannot have the type " <> typeText ty)) (\c -> pure (c, Fixed)) r

-- | A binary operator: untyped literals take the other operand's type, or
-- the expected type when both are untyped.
binaryExpr :: Maybe Type -> Pos -> BinOp -> Expr -> Expr -> C TExpr
binaryExpr expected p o a b = do
  pol <- asks envPol
  -- MT-OP-1, MT-OP-20: MasterTool's power is the function EXPT; its
  -- grammar has no operator **
  when (pSourceForm pol == MasterToolSource && o == BPow) $
    failC "expected-token" p "MasterTool XE has no operator **; EXPT(base, exponent) raises to a power (MT-OP-20)"
  let operandExpected = if o `elem` [BLt, BGt, BLe, BGe, BEq, BNe] then Nothing else expected
  -- an operand whose type depends on its literals (ABS(1), 16#FF OR 16#0F)
  -- takes the other operand's type, as an untyped literal does; the other
  -- operand's type is read from its text (typeHint), so that nothing is
  -- checked twice
  hA <- typeHint 6 a
  hB <- typeHint 6 b
  ta <- infer ((hB >>= numericTarget) `orElse` operandExpected) a
  tb <- infer ((hA >>= numericTarget) `orElse` operandExpected) b
  (ca, cb) <- case (isFlex ta, isFlex tb) of
    (True, False) -> (,) <$> adapt (ceType (fst tb)) ta <*> pure (fst tb)
    (False, True) -> (,) (fst ta) <$> adapt (ceType (fst ta)) tb
    (True, True) -> case operandExpected >>= numericTarget of
      Just t -> (,) <$> adapt t ta <*> adapt t tb
      Nothing -> (,) <$> settle ta <*> settle tb
    (False, False) -> pure (fst ta, fst tb)
  case pointerOperation o (plainEnum ca) (plainEnum cb) of
    Just r -> pure (r, Fixed)
    Nothing -> plain pol (plainEnum ca) (plainEnum cb)
  where
    -- NX-TYPE-60: CODESYS's enumerated values compute as their base type
    plainEnum c = case ceType c of
      TNumEnum _ e _ -> c {ceType = TElem e}
      _ -> c
    plain pol ca cb = do
      (ca', cb') <- widen pol ca cb
      case binaryType pol o (ceType ca') (ceType cb') of
        Right t
          -- MT-OP-4, MT-OP-11, MT-OP-12 (MT-VERR-13): MasterTool orders
          -- numbers only, and MOD takes integers only
          | pSourceForm pol == MasterToolSource, Just e <- baseElem (ceType ca'), not (masterToolOperand o e) ->
              failC "invalid-binary-operation" p ("the operation is not possible between two " <> elemName e <> " (MT-VERR-13)")
          | otherwise -> fixed p t (CBinary o ca' cb')
        Left msg
          | sameType (ceType ca') (ceType cb') -> failC "invalid-binary-operation" p msg
          | otherwise ->
              let cited = citing pol ["TC-CONV-1", "NX-CONV-1", "NX-CONV-2"]
               in -- binaryType's message about different types cites the rule already
                  failC "type-mismatch" p (if cited `T.isInfixOf` msg then msg else msg <> " " <> T.dropEnd 1 cited <> ": operands of one type)")
    -- NX-TYPE-77: an address plus or minus a number of bytes; addresses
    -- compared or subtracted as the DWORDs they are
    pointerOperation op ca cb = case (ceType ca, ceType cb) of
      (TPointer t, tb) | op `elem` [BAdd, BSub], isIntType tb -> Just (CExpr p (TPointer t) (CBinary op (word ca) (word cb)))
      (TPointer _, TPointer _) | op == BSub -> Just (CExpr p (TElem DWORD) (CBinary op (word ca) (word cb)))
      (TPointer _, tb) | comparison op, isIntType tb || isPointer tb -> Just (CExpr p (TElem BOOL) (CBinary op (word ca) (word cb)))
      (ta, TPointer _) | comparison op, isIntType ta -> Just (CExpr p (TElem BOOL) (CBinary op (word ca) (word cb)))
      _ -> Nothing
    comparison op = op `elem` [BEq, BNe, BLt, BGt, BLe, BGe]
    masterToolOperand op e
      | op == BMod = isAnyInt e
      | op `elem` [BLt, BGt, BLe, BGe] = isAnyNum e
      | otherwise = True
    isIntType t = maybe False isInt (baseElem t)
    isPointer = \case
      TPointer _ -> True
      _ -> False
    word c = case ceType c of
      TPointer _ -> c {ceType = TElem DWORD}
      TElem DWORD -> c
      _ -> CExpr (cePos c) (TElem DWORD) (CConvert (TElem DWORD) c)
    orElse x y = maybe y Just x
    numericTarget t = case baseElem t of
      Just e | isAnyNum e || isBitString e -> Just t
      _ -> Nothing
    -- a literal beside a TIME in * and / is a number (TC-OP-58, TC-OP-59)
    adapt t te = case baseElem t of
      Just e | isTimeLike e -> settle te
      _ -> coerceLit t te >>= maybe (settle te) pure
    widen pol ca cb
      | sameType (ceType ca) (ceType cb) = pure (ca, cb)
      | otherwise = case (baseElem (ceType ca), baseElem (ceType cb)) of
          (Just x, Just y)
            | implicitAllowed (pImplicitConversions pol) x y -> pure (CExpr (cePos ca) (ceType cb) (CConvert (ceType cb) ca), cb)
            | implicitAllowed (pImplicitConversions pol) y x -> pure (ca, CExpr (cePos cb) (ceType ca) (CConvert (ceType ca) cb))
          _ -> pure (ca, cb)

-- | The type an expression evidently has, read from its text without
-- checking it (a variable's declared type, a typed literal, a conversion's
-- result), looking at most @depth@ levels down; Nothing when it depends on
-- untyped literals only or the text has errors.
typeHint :: Int -> Expr -> C (Maybe Type)
typeHint depth e
  | depth <= 0 = pure Nothing
  | otherwise = case e of
      EVar {} -> viaRef
      EField {} -> viaRef
      EIndex {} -> viaRef
      ELocated _ l -> pure (Just (locationType l))
      ELit p (LTyped t _) -> (Just <$> resolveType (TSName p t)) `catchError` const (pure Nothing)
      EUn _ UNot x -> typeHint (depth - 1) x
      EUn _ _ x -> typeHint (depth - 1) x
      EBin _ o x y
        | o `elem` [BLt, BGt, BLe, BGe, BEq, BNe] -> pure (Just (TElem BOOL))
        | otherwise -> typeHint (depth - 1) x >>= maybe (typeHint (depth - 1) y) (pure . Just)
      ECall _ f args -> asks envPol >>= \pol -> case conversionName pol (key f) of
        Just (_, to) -> pure (Just (TElem to))
        Nothing | Just (_, result) <- libraryFunction pol (key f) -> pure (Just (TElem result))
        Nothing -> do
          pous <- asks envPous
          varsOf <- asks envVarsOf
          case M.lookup (key f) pous of
            Just pou | pouKind pou == KFunction -> pure (viType <$> find ((== key f) . viKey) (M.findWithDefault [] (key f) varsOf))
            _ -> firstJust [x | ArgPositional x <- args]
      _ -> pure Nothing
  where
    viaRef = (Just . (\(_, t, _) -> t) <$> checkRef e) `catchError` const (pure Nothing)
    firstJust [] = pure Nothing
    firstJust (x : xs) = typeHint (depth - 1) x >>= maybe (firstJust xs) (pure . Just)

-- | The offset of an address in bits from its segment's start: byte × 8
-- plus the bit (NX-OP-69).
bitOffset :: Location -> Integer
bitOffset l = case locAddress l of
  [b, bit] -> b * 8 + bit
  b : _ -> b * 8
  [] -> 0

-- | Where the code of the POUs lies (Stref.IEC.Memory lays out the data
-- below it): the address ADR gives a POU.
codeArea :: Integer
codeArea = 0xC0000000

-- | A function call in an expression: a conversion, a standard function or
-- a user FUNCTION.
callExpr :: Maybe Type -> Pos -> Text -> [Arg] -> C TExpr
callExpr expected p f args
  | key f == "ADR" = do
      pol <- asks envPol
      unless (pExtensions pol == ExtensionsCodesys) (failC "undeclared-function" p "ADR is a CODESYS operator (policy extensions = codesys)")
      case args of
        -- NX-TYPE-75, NX-OP-68: the address of a variable
        [ArgPositional x] -> do
          pous <- asks envPous
          locals <- asks envLocals
          case x of
            -- NX-TYPE-79: the address of a function, program or FB, a DWORD
            -- that no pointer of the program can follow (L5565-5569)
            EVar _ n | M.member (key n) pous, not (M.member (key n) locals) ->
              fixed p (TElem DWORD) (CConst (VInt DWORD (codeArea + 16 * toInteger (M.findIndex (key n) pous))))
            _ -> do
              (ref, t, _) <- checkRef x
              case ref of
                -- a BOOL at a bit address is not a byte a pointer can hold
                CLocated l (TElem BOOL) | not (byteSized l) ->
                  failC "not-a-variable" p ("ADR gives the address of a byte, and " <> locText l <> " is one bit of it: no pointer reaches a single bit (BITADR gives an input bit's address, NX-OP-69)")
                _ -> fixed p (pointerOf t) (CAddressOf ref)
        _ -> failC "too-many-arguments" p "ADR takes one variable"
  | key f == "BITADR" = do
      pol <- asks envPol
      unless (pExtensions pol == ExtensionsCodesys) (failC "undeclared-function" p "BITADR is a CODESYS operator (policy extensions = codesys)")
      found <- case args of
        [ArgPositional (EVar vp n)] -> lookupName vp n
        [_] -> pure Nothing
        _ -> failC "too-many-arguments" p "BITADR takes one variable"
      case found of
        -- NX-OP-69: the bit's offset in its segment, in a DWORD whose top
        -- bit marks the inputs (%IX2.3 is 16#80000013). The manual gives no
        -- other segment's mark, so only an input is accepted.
        Just (CLocated l _, _, _) | locArea l == 'I' -> fixed p (TElem DWORD) (CConst (VInt DWORD (0x80000000 + bitOffset l)))
        _ -> failC "not-a-variable" p "BITADR takes a variable located at an input address (%I...): the manual gives the value only for the inputs' segment (NX-OP-69)"
  | key f == "SIZEOF" = case args of
      -- TC-STR-12: the declared size in bytes, an integer of the context's type
      [ArgPositional x] -> do
        pol <- asks envPol
        t <- case x of
          -- CODESYS also takes a type's name (NX-OP-34)
          EVar vp n | pExtensions pol == ExtensionsCodesys -> do
            r <- lookupName vp n
            case r of
              Just (_, ty, _) -> pure ty
              Nothing -> resolveType (TSName vp n)
          _ -> ceType . fst <$> infer Nothing x
        case pExtensions pol of
          ExtensionsNone -> let n = sizeOf t in pure (CExpr p (TElem DINT) (CConst (VInt DINT n)), FlexInt n)
          ExtensionsCodesys -> do
            -- NX-OP-34: the bytes as the pointers see them (Stref.IEC.Memory),
            -- a USINT below 256, a UINT below 65536, then UDINT, ULINT
            n <- pointerStep t
            let e = head ([e' | e' <- [USINT, UINT, UDINT], fitInt e' n] ++ [ULINT])
            pure (CExpr p (TElem e) (CConst (VInt e n)), Fixed)
      _ -> failC "too-many-arguments" p "SIZEOF takes one variable"
  | key f == "TRUNC" = do
      -- TC-CONV-7: TRUNC gives an ANY_INT; the context chooses which
      (ce, flex) <- callStandard expected p f args
      case expected >>= baseElem of
        Just e | isAnyInt e, ceType ce /= TElem e -> pure (CExpr p (TElem e) (CConvert (TElem e) ce), flex)
        _ -> pure (ce, flex)
  | otherwise = callStandard expected p f args

-- | A MasterTool conversion to the type as the core's conversions: Table
-- 4-6's row for the value's type, the identity for the type itself; REAL
-- to WORD (C51) and, for ANY_TO_, to BYTE, USINT and DWORD (MT-CONV-7,
-- decision A8) truncate to DINT and keep that DINT's low bits, so two
-- conversions of the core (real-to-int, then narrow-int).
masterToolConversion :: Elem -> CExpr -> CNode
masterToolConversion to cx
  | sameType (ceType cx) (TElem to) = ceNode cx
  | ceType cx == TElem REAL, to `elem` [BYTE, WORD, DWORD, USINT] = CConvert (TElem to) (CExpr (cePos cx) (TElem DINT) (CConvert (TElem DINT) cx))
  | otherwise = CConvert (TElem to) cx

-- | MT-OP-21, MT-VERR-10: the functions a MasterTool module calls are EXPT,
-- the conversions of Table 4-6 (MT-CONV) and the module's functions
-- declared before the caller (MT-SCOPE-2); the core's other standard
-- functions (ABS, SQRT, SHL, REAL_TO_BYTE, ...) are not declared.
masterToolFunction :: Pos -> Text -> C ()
masterToolFunction p f = do
  pous <- asks envPous
  caller <- asks envPou
  let k = key f
      declaredBefore = case (M.lookup k pous, caller) of
        (Just callee, Just c) -> key (pouName c) == k || pouPos callee < pouPos c
        (Just _, Nothing) -> True
        _ -> False
  unless (k == "EXPT" || hasConversion k || declaredBefore) $
    failC "undeclared-function" p ("the function " <> f <> " is not declared; a module calls EXPT, the conversions and its functions declared before the call (MT-VERR-10, MT-OP-21)")

-- | The size in bytes of a variable of the type (TC-STR-12): C's layout
-- without padding, a STRING[n] with its terminating NUL (TC-TYPE-24).
sizeOf :: Type -> Integer
sizeOf = \case
  TElem e
    | e == BOOL -> 1
    | isInt e -> toInteger (intBits e `div` 8)
    | e `elem` [LREAL, LTIME] -> 8
    | otherwise -> 4
  TString w n -> (if w then 2 else 1) * (toInteger n + 1)
  TArray bs t -> product [hi - lo + 1 | (lo, hi) <- bs] * sizeOf t
  TStruct _ fs -> sum (map (sizeOf . snd) fs)
  TUnion _ fs -> maximum (0 : map (sizeOf . snd) fs)
  TEnum _ _ -> 2
  TNumEnum _ e _ -> sizeOf (TElem e)
  TSubrange e _ _ -> sizeOf (TElem e)
  TFB _ -> 0
  TProgram _ -> 0
  TPointer _ -> 4 -- NX-TYPE-78: an address is a DWORD
  TNamed _ -> 0 -- only a pointer's target

callStandard :: Maybe Type -> Pos -> Text -> [Arg] -> C TExpr
callStandard expected p f args = do
  pol <- asks envPol
  pous <- asks envPous
  let k = key f
  let mt = pSourceForm pol == MasterToolSource
  when mt (masterToolFunction p f)
  -- MT-OP-20: EXPT's exponent is a USINT
  case args of
    [_, ArgPositional ex] | mt, k == "EXPT" -> () <$ (checkExprAt (Just (TElem USINT)) ex >>= assignable (TElem USINT))
    _ -> pure ()
  case conversionName pol k of
    -- MT-CONV-8: ANY_TO_<T> converts by the row of Table 4-6 for its
    -- argument's type (the identity for T itself)
    _ | mt, Just to <- T.stripPrefix "ANY_TO_" k >>= parseElemName -> do
      a <- positionalOnly
      case a of
        [x] -> do
          te <- infer Nothing x
          cx <- case te of
            (_, FlexReal _) -> coerceLit (TElem REAL) te >>= maybe (settle te) pure
            _ -> settle te
          fixed p (TElem to) (masterToolConversion to cx)
        _ -> failC "too-many-arguments" p (f <> " takes one argument")
    Just (from, to) -> do -- TC-CONV-6
      a <- positionalOnly
      case a of
        [x] -> do
          cx0 <- checkExprAt (Just (TElem from)) x
          -- MT-CONV-6: MasterTool widens a conversion's argument as any
          -- other value (a USINT given to INT_TO_REAL)
          cx <- if mt then assignable (TElem from) cx0 else pure cx0
          -- the argument has the type named first (TC-CONV-6, NX-CONV-10)
          unless (sameType (ceType cx) (TElem from)) (failC "type-mismatch" (exprPos x) (f <> " converts a " <> elemName from <> ", not a " <> typeText (ceType cx) <> " " <> citing pol ["TC-CONV-6", "NX-CONV-10"]))
          if mt
            then fixed p (TElem to) (masterToolConversion to cx)
            else fixed p (resultOf to cx) (CConvert (resultOf to cx) cx)
        _ -> failC "too-many-arguments" p (f <> " takes one argument")
    Nothing -> case M.lookup k pous of
      Just pou
        | pouKind pou == KFunction -> userCall pou
        | otherwise -> failC "not-a-function" p (f <> " is not a function")
      Nothing | Just (params, result) <- libraryFunction pol k -> libraryCall params result
      Nothing -> do
        a <- positionalOnly
        -- an expression of untyped literals in an argument takes the type
        -- the call's context expects, as it would without the call
        tes <- mapM (infer (expected >>= numericLike)) a
        -- the selector of MUX and SEL does not type their inputs
        let nonFlex = [ceType c | (i, (c, Fixed)) <- zip [0 :: Int ..] tes, not (i == 0 && k `elem` ["MUX", "SEL"])]
            -- NX-OP-50: a constant shifted or rotated takes the smallest
            -- type that holds it, whatever the context expects
            smallest = case tes of
              (_, FlexInt n) : _ | k `elem` shiftNames, pExtensions pol == ExtensionsCodesys ->
                take 1 [TElem e | e <- [BYTE, WORD, DWORD, LWORD], fitInt e n]
              _ -> []
            candidates = map Just smallest ++ [Just t | t <- take 1 nonFlex] ++ [expected >>= numericLike, Nothing]
        r <- firstOk pol False tes candidates >>= maybe (firstOk pol True tes candidates) (pure . Just)
        case r of
          Just (cs, t) -> fixed p t (CStandard k cs)
          Nothing -> do
            cs <- widened pol k <$> mapM settle tes
            case standardType pol k (map ceType cs) of
              Nothing -> failC "undeclared-function" p ("the function " <> f <> " is not declared")
              Just (Left msg)
                | Just names <- standardParameters pol k (length cs), length cs > length names -> failC "too-many-arguments" p msg
                | Just names <- standardParameters pol k (length cs), length cs < length names -> failC "too-few-arguments" p msg
                | otherwise -> failC "type-mismatch" p msg
              Just (Right t) -> fixed p t (CStandard k cs)
  where
    numericLike t = case baseElem t of
      Just e | isAnyNum e || isAnyBit e -> Just t
      _ -> Nothing
    resultOf to cx = case (to, ceType cx) of
      _ -> TElem to
    -- TC-POU-11: formal arguments in any order, placed by their names
    positionalOnly = case [a | a@ArgInput {} <- args] of
      [] -> forM args $ \case
        ArgPositional e -> pure e
        ArgInput _ _ e -> pure e
        ArgOutput ap _ _ -> failC "not-a-function-block" ap "=> binds outputs of function blocks only"
      formal -> do
        pol <- asks envPol
        when (length formal /= length args) (failC "mixed-arguments" p ("the call of " <> f <> " mixes formal and positional arguments " <> citing pol ["TC-POU-12", "NX-POU-12", "NX-ERR-30"]))
        case standardParameters pol (key f) (length formal) of
          Nothing -> pure [e | ArgInput _ _ e <- formal]
          Just names -> forM names $ \n -> case [e | ArgInput _ m e <- formal, key m == n] of
            [e] -> pure e
            _ -> failC "unknown-parameter" p (f <> " takes the inputs " <> T.intercalate ", " names)
    -- each untyped literal argument takes the candidate type or its own
    -- default (SHL(16#0F, 1) into a BYTE: IN is BYTE, N stays DINT); the
    -- first combination the function accepts wins
    -- first every untyped literal takes the candidate type (SEL(g, 10, 20)
    -- into an INT); then, mixing, each takes the candidate or its default
    -- (SHL(16#0F, 1) into a BYTE: IN is BYTE, N stays DINT)
    firstOk _ _ _ [] = pure Nothing
    firstOk pol mixing tes (c : cs) = do
      options <- forM tes $ \te@(ce, _) ->
        if isFlex te
          then do
            typed <- maybe (pure Nothing) (`coerceLit` te) c
            settled <- settle te
            pure $ case (typed, mixing) of
              (Just x, True) -> [x, settled]
              (Just x, False) -> [x]
              (Nothing, True) -> [settled]
              (Nothing, False) -> [settled | c == Nothing]
          else pure [ce]
      case [(xs', t) | xs <- take 64 (sequence options), let xs' = widened pol (key f) xs, Just (Right t) <- [standardType pol (key f) (map ceType xs')]] of
        (r : _) -> pure (Just r)
        [] -> firstOk pol mixing tes cs
    -- NX-CONV-1..3 (policy implicit-conversions): inputs of MAX, MIN,
    -- LIMIT, SEL and MUX of different types are converted to the one the
    -- others widen to implicitly, as an operator's operands are; none such:
    -- left as they are, for the function's own message
    widened pol k cs = fromMaybe cs $ do
      let inputs = [c | (i, c) <- zip [0 :: Int ..] cs, i >= firstInput k]
      t0 : ts <- Just (map ceType inputs)
      t <- foldM (wider pol) t0 ts
      Just [if i >= firstInput k && not (sameType (ceType c) t) then CExpr (cePos c) t (CConvert t c) else c | (i, c) <- zip [0 :: Int ..] cs]
    firstInput k
      | k `elem` ["MAX", "MIN", "LIMIT"] = 0
      | k `elem` ["SEL", "MUX"] = 1
      | otherwise = maxBound
    wider pol a b
      | sameType a b = Just a
      | otherwise = case (baseElem a, baseElem b) of
          (Just x, Just y)
            | implicitAllowed (pImplicitConversions pol) x y -> Just (TElem y)
            | implicitAllowed (pImplicitConversions pol) y x -> Just (TElem x)
          _ -> Nothing
    userCall pou = do
      vars <- asks (fromMaybe [] . M.lookup (key (pouName pou)) . envVarsOf)
      -- MT-POU-5 (MT-VERR-20): a MasterTool call gives every input
      let given = length args
          inputs = length [v | v <- vars, viSection v == SecInput]
      mt <- masterToolSource
      when (mt && given < inputs) $
        failC "too-few-arguments" p (f <> " takes " <> T.pack (show inputs) <> " argument(s) but is called with " <> T.pack (show given) <> " (MT-VERR-20)")
      (inputs, inouts, outputs) <- bindArgs p (pouName pou) vars args
      pol <- asks envPol
      unless (null outputs || pExtensions pol == ExtensionsCodesys) (failC "section-not-allowed" p "a FUNCTION has no outputs to bind with => (TC-VAR-10)")
      let result = fromMaybe (TElem BOOL) (viType <$> find ((== key (pouName pou)) . viKey) vars)
      fixed p result (CCall (key (pouName pou)) inputs inouts outputs)
    -- util.library's functions and TIME() (standard-library = codesys,
    -- NX-FB-34..37, NX-OP-87): bound as a user function's parameters, so
    -- that untyped literals take the parameters' types (BCD_TO_INT(73): a
    -- BYTE) and formal arguments may come in any order; an input left out
    -- is the type's zero (TC-POU-9)
    libraryCall params result = do
      let vars = [VarInfo n n SecInput (TElem e) (defaultValue (TElem e)) False Nothing Nothing p Volatile | (n, e) <- params]
      (inputs, _, outputs) <- bindArgs p f vars args
      unless (null outputs) (failC "section-not-allowed" p "a FUNCTION has no outputs to bind with => (TC-VAR-10)")
      let argOf (n, e) = fromMaybe (CExpr p (TElem e) (CConst (defaultValue (TElem e)))) (lookup n inputs)
      fixed p (TElem result) (CStandard (key f) (map argOf params))

-- | Arguments against a POU's parameters (TC-POU-11, TC-POU-33..36):
-- positional in the order of the inputs (and in-outs), or formal; never
-- both (TC-POU-12).
bindArgs :: Pos -> Text -> [VarInfo] -> [Arg] -> C ([(Text, CExpr)], [(Text, CRef)], [(Text, CRef, Type)])
bindArgs p callee vars args = do
  let positional = [e | ArgPositional e <- args]
      formal = [a | a <- args, not (isPositional a)]
      params = [v | v <- vars, viSection v `elem` [SecInput, SecInOut]]
  pol <- asks envPol
  when (not (null positional) && not (null formal)) $
    failC "mixed-arguments" p ("the call of " <> callee <> " mixes formal (name := value) and positional arguments " <> citing pol ["TC-POU-12", "NX-POU-12", "NX-ERR-30"])
  named <-
    if null formal
      then do
        when (length positional > length params) (failC "too-many-arguments" p (callee <> " takes " <> T.pack (show (length params)) <> " arguments, not " <> T.pack (show (length positional))))
        pure (zipWith (\v e -> (viKey v, Left e)) params positional)
      else forM formal $ \case
        ArgInput ap n e -> case find ((== key n) . viKey) vars of
          Just v | viSection v `elem` [SecInput, SecInOut] -> pure (viKey v, Left e)
          _ -> failC "unknown-parameter" ap (callee <> " has no input named " <> n)
        ArgOutput ap n e -> case find ((== key n) . viKey) vars of
          Just v | viSection v == SecOutput -> pure (viKey v, Right e)
          _ -> failC "unknown-parameter" ap (callee <> " has no output named " <> n)
        ArgPositional _ -> failC "mixed-arguments" p "positional argument"
  either throwError pure (runExcept (checkDuplicates [(p, k) | (k, _) <- named]))
  ins <- fmap catMaybes $ forM named $ \(k, a) -> case (a, find ((== k) . viKey) vars) of
    (Left e, Just v) | viSection v == SecInput -> do
      ce <- checkExprAt (Just (viType v)) e >>= assignable (viType v)
      pure (Just (k, ce))
    _ -> pure Nothing
  inouts <- fmap catMaybes $ forM named $ \(k, a) -> case (a, find ((== k) . viKey) vars) of
    (Left e, Just v) | viSection v == SecInOut -> do
      (ref, ty) <- checkTarget e
      case ref of
        CBit {} -> failC "invalid-bit-access" (exprPos e) ("a bit cannot be passed to the VAR_IN_OUT " <> viName v <> " (NX-OP-97)")
        _ -> pure ()
      -- TC-VAR-3, TC-VAR-4: by reference, so the very type (a STRING's
      -- capacity, a subrange's bounds)
      unless (ty == viType v) (failC "type-mismatch" (exprPos e) ("the in-out parameter " <> viName v <> " takes a variable of type " <> typeText (viType v) <> ", not " <> typeText ty))
      pure (Just (k, ref))
    _ -> pure Nothing
  outs <- fmap catMaybes $ forM named $ \(k, a) -> case (a, find ((== k) . viKey) vars) of
    (Right e, Just v) -> do
      (ref, ty) <- checkTarget e
      unless (sameType ty (viType v)) (failC "type-mismatch" (exprPos e) ("the output " <> viName v <> " is a " <> typeText (viType v) <> ", bound to a " <> typeText ty))
      pure (Just (k, ref, ty))
    _ -> pure Nothing
  let missingInOut = [v | v <- params, viSection v == SecInOut, viKey v `notElem` map fst inouts]
  case missingInOut of
    (v : _) -> failC "too-few-arguments" p ("the in-out parameter " <> viName v <> " of " <> callee <> " must be given a variable")
    [] -> pure ()
  pure (ins, inouts, outs)
  where
    isPositional = \case
      ArgPositional _ -> True
      _ -> False

-- | A call statement: an FB instance, or a function whose result is dropped.
checkCallStmt :: Pos -> Expr -> [Arg] -> C CStmt
checkCallStmt p callee args = do
  pous <- asks envPous
  pol <- asks envPol
  member' <- case callee of
    EDeref _ (ESuper _) -> pure Nothing
    _ -> memberCall p callee args
  case callee of
    _ | Just ce <- member' -> pure (CEval p ce)
    EDeref sp (ESuper _) -> do
      -- NX-POU-46: SUPER^() runs the base FB's body on this instance
      (_, b) <- superOf sp
      vars <- fbVars b
      (ins, inouts, outs) <- bindArgs p b vars args
      pure (CCallFB p (FBCall CThis (key b) ins inouts outs))
    EVar _ n | isFunctionName pol pous n -> do
      locals <- asks envLocals
      if M.member (key n) locals
        then fbCall
        else do
          (ce, _) <- callExpr Nothing p n args
          pure (CEval p ce)
    _ -> fbCall
  where
    isFunctionName pol pous n = case M.lookup (key n) pous of
      Just pou -> pouKind pou == KFunction
      Nothing -> key n `elem` standardFunctionNames || isJust (conversionName pol (key n)) || isJust (libraryFunction pol (key n))
    fbCall = do
      pous' <- asks envPous
      case callee of
        EVar _ n | Just pou <- M.lookup (key n) pous', pouKind pou == KProgram -> do
          pol <- asks envPol
          caller <- asks (fmap pouKind . envPou)
          case pProgramCalls pol of
            ProgramCallsForbidden -> failC "program-call" p ("the PROGRAM " <> n <> " is run by a task; a POU cannot call it (TC-POU-44)")
            ProgramCallsAllowed
              | caller == Just KFunction -> failC "program-call" p ("a FUNCTION cannot call the PROGRAM " <> n <> " (NX-POU-2)")
              | otherwise -> pure ()
        _ -> pure ()
      (ref, ty, access) <- checkRef callee
      case access of
        Hidden why -> failC "read-not-allowed" p why -- TC-POU-23
        WriteOnly why -> failC "read-not-allowed" p why
        _ -> pure ()
      case ty of
        TFB fb -> do
          vars <- fbVars fb
          (ins, inouts, outs) <- bindArgs p fb vars args
          pure (CCallFB p (FBCall ref (key fb) ins inouts outs))
        TProgram prg -> do
          -- NX-POU-4: PRG(IN_VAR := 33, OUT_VAR => erg)
          vars <- fbVars prg
          (ins, inouts, outs) <- bindArgs p prg vars args
          pure (CCallFB p (FBCall ref (key prg) ins inouts outs))
        _ -> failC "not-a-function-block" (exprPos callee) ("this is not a function block instance but a " <> typeText ty)

-- | TC-POU-2: no POU calls itself, directly or through others (also through
-- a global FB instance or an instance inside another); and no function
-- block contains an instance of itself. One depth-first walk over the call
-- graph (linear in its size): the first call that closes a cycle is the
-- error.
checkRecursion :: Policies -> Bool -> [Pou] -> [VarBlock] -> Except VerificationError ()
checkRecursion pol containment pous globalBlocks =
  if containment then walk "recursive-type" containEdges else walk "recursive-call" callEdges
  where
    byKey = M.fromList [(key (pouName p), p) | p <- pous]
    isPou t = M.member (key t) byKey
    -- the FB type a declaration holds, directly or as array elements
    fbOf = \case
      TSName _ t | isPou t -> Just (key t)
      TSArray _ _ t -> fbOf t
      _ -> Nothing
    declTypes blocks = M.fromList [(key n, t) | b <- blocks, d <- vbDecls b, Just t <- [fbOf (vdType d)], (_, n) <- vdNames d]
    globalTypes = declTypes globalBlocks
    varTypesOf t = maybe M.empty (declTypes . pouVars) (M.lookup t byKey)
    containEdges p = [(t, vdPos d) | pouKind p == KFunctionBlock, b <- pouVars p, d <- vbDecls b, Just t <- [fbOf (vdType d)]]
    callEdges p =
      let local = declTypes (pouVars p)
          -- the FB type an expression names: a variable, an element, a field
          calleeType = \case
            EVar _ n -> M.lookup (key n) local <|> M.lookup (key n) globalTypes
            EIndex _ e _ -> calleeType e
            EField _ e f -> calleeType e >>= \t -> M.lookup (key f) (varTypesOf t)
            _ -> Nothing
          stmtCalls = \case
            SAssign _ a b -> exprCalls a ++ exprCalls b
            SCall q e args -> [(t, q) | Just t <- [calleeType e]] ++ [(key n, q) | EVar _ n <- [e], isPou n] ++ exprCalls e ++ concatMap argCalls args
            SIf _ arms els -> concat [exprCalls c ++ concatMap stmtCalls b | (c, b) <- arms] ++ concatMap stmtCalls els
            SCase _ sel arms els -> exprCalls sel ++ concatMap (concatMap stmtCalls . snd) arms ++ concatMap stmtCalls els
            SFor _ _ a b c body -> concatMap exprCalls ([a, b] ++ maybe [] pure c) ++ concatMap stmtCalls body
            SWhile _ c b -> exprCalls c ++ concatMap stmtCalls b
            SRepeat _ b c -> exprCalls c ++ concatMap stmtCalls b
            _ -> []
          argCalls = \case
            ArgPositional e -> exprCalls e
            ArgInput _ _ e -> exprCalls e
            ArgOutput {} -> []
          exprCalls = \case
            ECall q n args -> [(key n, q) | isPou n] ++ concatMap argCalls args
            EUn _ _ a -> exprCalls a
            EBin _ _ a b -> exprCalls a ++ exprCalls b
            EField _ a _ -> exprCalls a
            EIndex _ a is -> exprCalls a ++ concatMap exprCalls is
            _ -> []
       in concatMap stmtCalls (pouBody p)
    walk kind edgesOf = go S.empty (map (key . pouName) pous)
      where
        go _ [] = pure ()
        go done (r : rest)
          | r `S.member` done = go done rest
          | otherwise = visit done [r] r >>= \done' -> go done' rest
        visit done path node = do
          let out = maybe [] edgesOf (M.lookup node byKey)
          foldM (step path node) (S.insert node done) out
        step path node done (callee, q)
          | callee `elem` path =
              throwError (VerificationError kind q (nameOf node <> (if kind == "recursive-type" then " contains " else " calls ") <> nameOf callee <> ", which leads back to " <> nameOf callee <> ": POUs are not recursive " <> citing pol ["TC-POU-2", "NX-POU-50"]))
          | callee `S.member` done = pure done
          | otherwise = visit done (callee : path) callee
    nameOf k = maybe k pouName (M.lookup k byKey)

-- | The type a direct address denotes (TC-ADDR-4, TC-ADDR-5): IEC sizes X
-- (or none) a bit, B a byte, W a word, D a double word, L a long word;
-- Tecomat's areas without a size prefix a byte (with a bit number, a bit)
-- and L a 32-bit long.
locationType :: Location -> Type
locationType l = TElem $ case (locSize l, length (locAddress l)) of
  ('X', _) -> BOOL
  ('B', _) -> BYTE
  ('W', _) -> WORD
  ('D', _) -> DWORD
  ('L', _) | tecomatArea -> DWORD
  ('L', _) -> LWORD
  (_, 2) -> BOOL
  _ | tecomatArea -> BYTE
  _ -> BOOL
  where
    tecomatArea = locArea l `elem` ("XYSR" :: String)


-- | Data without instances, which a union's bytes can hold.
plainData :: Type -> Bool
plainData = \case
  TFB _ -> False
  TProgram _ -> False
  TArray _ t -> plainData t
  TStruct _ fs -> all (plainData . snd) fs
  TUnion _ fs -> all (plainData . snd) fs
  _ -> True
