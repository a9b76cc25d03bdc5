-- | One conformance case: a complete ST compilation unit whose first comment,
-- opened by @(*---@ and closed by @---*)@, holds its metadata as YAML
-- (conformance/README.md, "A case").
--
-- Loading validates everything a runner later relies on: every key is known,
-- every operand exists in the case's PLC layout, every value fits its
-- operand, every rule id is in the dialect's RULES index. Problems are
-- reported as @file:line: message@, with the line of the file.
module Stref.Conformance.Case
  ( Case (..)
  , Status (..)
  , PlcSetup (..)
  , CallSetup (..)
  , Expect (..)
  , emptyExpect
  , Conditional (..)
  , ExpValue (..)
  , ExpVerdict (..)
  , ExpError (..)
  , ExpReject (..)
  , CaseOrigin (..)
  , IecSetup (..)
  , IecCall (..)
  , iecScalar
  , parseCase
  , parseScenario
  , effectiveExpect
  , expectedVerdict
  , expValueScalar
  , renderExpValue
  , operandIsReal
  , operandBits
  , inDiagnosticBand
  , extractMetadata
  ) where

import Control.Monad (forM, unless, when, (<=<))
import Data.Aeson (Value (..))
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import Data.Char (isDigit)
import Data.List (sortOn)
import Data.Map.Strict (Map)
import qualified Data.Map.Strict as M
import Data.Scientific (Scientific, base10Exponent, floatingOrInteger)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Vector as V
import Data.Word (Word32)
import qualified Data.Yaml as Y
import Stref.Checked (ModuleKind (..))
import Stref.Conformance.Protocol (Scalar (..), bitsText, parseBits, scalarFromFloat, scientificToFloat)
import Stref.Operands
import Stref.Policy (Model (..), Policies (..), PolicyInfo (..), lookupPolicy, lookupPreset, policyTable)
import Stref.Values (realBits)

-- | @status@: where the expectation comes from.
data Status = Normative | PolicyDependent | Erratum
  deriving (Eq, Show)

-- | A value as a case writes it.
data ExpValue
  = EInt Integer
  | EBool Bool
  | EReal Float -- ^ a decimal, rounded to binary32 (nearest, ties to even)
  | EBits Word32
  | ENaN
  | EDecimal Scientific -- ^ IEC dialects: a decimal, rounded once to the variable's type (§4.2)
  | EText Text -- ^ IEC dialects: an ST literal, compared by value (§4.2)
  | EList [ExpValue] -- ^ a whole array
  | EMap (Map Text ExpValue) -- ^ a whole structure
  deriving (Show)

instance Eq ExpValue where
  EInt a == EInt b = a == b
  EBool a == EBool b = a == b
  EReal a == EReal b = realBits a == realBits b
  EBits a == EBits b = a == b
  ENaN == ENaN = True
  EDecimal a == EDecimal b = a == b
  EText a == EText b = a == b
  EList a == EList b = a == b
  EMap a == EMap b = a == b
  _ == _ = False

data ExpVerdict = ExpOk | ExpRejected | ExpRuntimeError
  deriving (Eq, Show)

-- | @error: none@, or a code with optional line and complements.
data ExpError
  = ErrNone
  | ErrCode Int (Maybe Int) (Maybe (Int, Int, Int))
  | ErrKind Text (Maybe Int) -- ^ IEC dialects: the kind of §4.3 and the line
  deriving (Eq, Show)

-- | @reject: {line, kind}@, both optional.
data ExpReject = ExpReject {rjLine :: Maybe Int, rjKind :: Maybe Text}
  deriving (Eq, Show)

-- | What must hold after the last call. Unstated parts are not compared.
data Expect = Expect
  { exVerdict :: Maybe ExpVerdict
  , exOperands :: Map Operand ExpValue
  , exVars :: Map Text ExpValue
  , exOutputs :: Map Int Bool -- ^ 1..3
  , exError :: Maybe ExpError
  , exReject :: Maybe ExpReject
  }
  deriving (Eq, Show)

emptyExpect :: Expect
emptyExpect = Expect Nothing M.empty M.empty M.empty Nothing Nothing

-- | An @expect-if@ entry: expectations that hold under these policy choices.
data Conditional = Conditional
  { cdWhen :: [(Text, Text)]
  , cdExpect :: Expect
  }
  deriving (Eq, Show)

data PlcSetup = PlcSetup
  { psConfig :: PlcConfig -- ^ the declared operands and the diagnostic band
  , psInit :: [(Operand, ExpValue)] -- ^ sorted: whole words before their bits
  , psChf :: Maybe ([Text], [Text]) -- ^ CHF in/out parameters as written (validated)
  }
  deriving (Eq, Show)

data CallSetup = CallSetup
  { csInputs :: (Bool, Bool, Bool)
  , csSet :: [(Operand, ExpValue)]
  }
  deriving (Eq, Show)

data Case = Case
  { caseId :: Text -- ^ @mastertool-xe/arith/int-add-saturates@
  , caseFile :: FilePath
  , caseDialect :: Text
  , caseArea :: Text
  , caseSource :: Text
  , caseDescription :: Text
  , caseRules :: [Text]
  , caseFeatures :: [Text]
  , caseStatus :: Status
  , caseModule :: ModuleKind
  , casePlc :: PlcSetup
  , caseCalls :: [CallSetup]
  , caseExpect :: Expect
  , caseExpectIf :: [Conditional]
  , caseIec :: Maybe IecSetup -- ^ the IEC dialects' keys (corpus-format §4.1)
  }
  deriving (Eq, Show)

-- | What an IEC case sets up: the program, the task interval, the located
-- variables before the first cycle and the variables written before each
-- cycle (one entry per cycle).
data IecSetup = IecSetup
  { iecProgram :: Maybe Text
  , iecCycle :: Text -- ^ a TIME literal, @T#10ms@ unless stated
  , iecInit :: [(Text, ExpValue)]
  , iecCalls :: [IecCall]
  }
  deriving (Eq, Show)

-- | One entry of an IEC case's calls: a cycle after writing variables, or
-- a reset of the controller that runs no cycle (docs/nexto.md).
data IecCall = IecCall
  { icSet :: [(Text, ExpValue)]
  , icReset :: Maybe Text
  }
  deriving (Eq, Show)

-- | Where a case file lies in its corpus: its id, dialect and area, derived
-- by the loader from the path.
data CaseOrigin = CaseOrigin
  { coId :: Text
  , coDialect :: Text
  , coArea :: Text
  }
  deriving (Eq, Show)

-- | The expectation under the given policies: @expect@, then every matching
-- @expect-if@ entry in order, each overriding the keys it states (maps are
-- merged operand by operand). An entry's verdict, stated or inferred from
-- its keys, replaces the earlier one and drops what no longer applies: an
-- error code under a new @ok@ or @rejected@, a @reject@ under a run.
effectiveExpect :: Policies -> Case -> Expect
effectiveExpect pol c = foldl mergeExpect (caseExpect c) [cdExpect d | d <- caseExpectIf c, all holds (cdWhen d)]
  where
    holds (name, choice) = maybe False (\info -> piGet info pol == choice) (lookupPolicy name)

-- | An @expect-if@ entry laid over the expectation it refines.
mergeExpect :: Expect -> Expect -> Expect
mergeExpect a b =
  let v = entryVerdict
   in Expect
        { exVerdict = maybe (exVerdict a) Just v
        , exOperands = M.union (exOperands b) (exOperands a)
        , exVars = M.union (exVars b) (exVars a)
        , exOutputs = M.union (exOutputs b) (exOutputs a)
        , exError = case (exError b, v) of
            (Just e, _) -> Just e
            (Nothing, Just ExpRejected) -> Nothing
            (Nothing, Just ExpOk) | Just ErrCode {} <- exError a -> Nothing
            (Nothing, Just ExpOk) | Just ErrKind {} <- exError a -> Nothing
            _ -> exError a
        , exReject = case (exReject b, v) of
            (Just r, _) -> Just r
            (Nothing, Just ExpRejected) -> exReject a
            (Nothing, Just _) -> Nothing
            (Nothing, Nothing) -> exReject a
        }
  where
    entryVerdict = case exVerdict b of
      Just v -> Just v
      Nothing
        | Just _ <- exReject b -> Just ExpRejected
        | Just ErrCode {} <- exError b -> Just ExpRuntimeError
        | Just ErrKind {} <- exError b -> Just ExpRuntimeError
        | Just ErrNone <- exError b -> Just ExpOk
        | otherwise -> Nothing

-- | The verdict a case expects: as stated, else @rejected@ when a @reject@
-- is stated, @runtime-error@ when an error code is stated, else @ok@.
expectedVerdict :: Expect -> ExpVerdict
expectedVerdict e = case exVerdict e of
  Just v -> v
  Nothing
    | Just _ <- exReject e -> ExpRejected
    | Just ErrCode {} <- exError e -> ExpRuntimeError
    | Just ErrKind {} <- exError e -> ExpRuntimeError
    | otherwise -> ExpOk

operandIsReal :: Operand -> Bool
operandIsReal = \case
  OpSimple KF _ -> True
  OpTablePos TF _ _ -> True
  _ -> False

-- | The width of an operand's bit pattern; 1 for a bit.
operandBits :: Operand -> Int
operandBits = \case
  OpBit {} -> 1
  op -> cellWidth (operandCell op)

-- | The five diagnostic operands are always configured (corpus-format §1).
inDiagnosticBand :: PlcConfig -> Operand -> Bool
inDiagnosticBand cfg = \case
  OpSimple KM a -> inBand a
  OpBit KM a _ -> inBand a
  _ -> False
  where
    inBand a = a >= plcDiagnostics cfg && a < plcDiagnostics cfg + 5

-- | How a value goes into a request for an operand.
expValueScalar :: Operand -> ExpValue -> Scalar
expValueScalar op = \case
  EInt n
    | operandIsReal op -> scalarFromFloat (fromInteger n)
    | otherwise -> SNumber (fromInteger n)
  EBool b -> SBool b
  EReal f -> scalarFromFloat f
  EBits w -> SBits w
  ENaN -> SBits 0x7FC00000
  v -> iecScalar v

-- | How an IEC case's value goes into a request (§4.2, §4.4).
iecScalar :: ExpValue -> Scalar
iecScalar = \case
  EInt n -> SNumber (fromInteger n)
  EBool b -> SBool b
  EReal f -> scalarFromFloat f
  EBits w -> SBits w
  ENaN -> SNaN
  EDecimal d -> SNumber d
  EText t -> SText t
  EList xs -> SList (map iecScalar xs)
  EMap m -> SMap (M.map iecScalar m)

renderExpValue :: ExpValue -> Text
renderExpValue = \case
  EInt n -> T.pack (show n)
  EBool b -> if b then "true" else "false"
  EReal f -> T.pack (show f)
  EBits w -> "{bits: " <> bitsText w <> "}"
  ENaN -> "nan"
  EDecimal d -> T.pack (show d)
  EText t -> t
  EList xs -> "[" <> T.intercalate ", " (map renderExpValue xs) <> "]"
  EMap m -> "{" <> T.intercalate ", " [k <> ": " <> renderExpValue v | (k, v) <- M.toList m] <> "}"

-- * Reading the file

-- | The YAML text of the metadata and the 1-based file line on which it
-- starts (the line of @(*---@), or an error with its line.
extractMetadata :: Text -> Either (Int, Text) (Int, Text)
extractMetadata src =
  case T.breakOn "(*" src of
    (_, rest) | T.null rest -> Left (1, "the case has no metadata: its first comment must open with (*--- and close with ---*)")
    (before, rest)
      | not ("(*---" `T.isPrefixOf` rest) ->
          Left (lineOf before, "the first comment of a case must be its metadata, opened by (*---")
      | otherwise ->
          let body = T.drop 5 rest
           in case T.breakOn "---*)" body of
                (_, close) | T.null close -> Left (lineOf before, "the metadata comment opened here is never closed by ---*)")
                (yaml, _) -> Right (lineOf before, yaml)
  where
    lineOf before = 1 + T.count "\n" before

-- | A path inside the metadata: keys, and list positions as @[n]@.
type Path = [Text]

type V = Either (Path, Text)

failAt :: Path -> Text -> V a
failAt p m = Left (p, m)

-- | A scenario (@stref run --scenario FILE@): a YAML list of calls as a
-- case's @calls:@ key of the dialect takes them (corpus-format §3 and §4.1),
-- read by the case reader itself; errors name the scenario file's lines.
parseScenario :: FilePath -> Text -> Text -> Either Text Case
parseScenario file dialect yaml =
  either (Left . relocate) Right $
    parseCase "<scenario>" (CaseOrigin "scenario" dialect "scenario") (const True) doc
  where
    doc = T.unlines (["(*---", "description: scenario", "rules: [SCENARIO]", "calls:"] ++ map ("  " <>) (T.lines yaml) ++ ["---*)"])
    -- "<scenario>:L: message", L counted in doc, whose line 5 is the file's 1
    relocate e = case T.breakOn ": " <$> T.stripPrefix "<scenario>:" e of
      Just (l, rest) | [(n, "")] <- reads (T.unpack l) -> T.pack file <> ":" <> T.pack (show (max 1 (n - 4 :: Int))) <> rest
      _ -> T.pack file <> ": " <> e

-- | Parse a case from its text. The origin comes from the file's place in
-- the corpus; @known@ tells whether a rule id is in the RULES index.
parseCase :: FilePath -> CaseOrigin -> (Text -> Bool) -> Text -> Either Text Case
parseCase file origin knownRule src = do
  (start, yamlText) <- either (\(l, m) -> Left (at l m)) Right (extractMetadata src)
  value <- case Y.decodeEither' (TE.encodeUtf8 yamlText) of
    Left e -> Left (at (start + yamlLine e) (yamlMessage e))
    Right v -> Right v
  let yamlLines = T.lines yamlText
  either (\(p, m) -> Left (at (start + locate yamlLines p) (describePath p <> m))) Right (caseFromYaml value)
  where
    at :: Int -> Text -> Text
    at l m = T.pack file <> ":" <> T.pack (show l) <> ": " <> m
    yamlLine = \case
      Y.InvalidYaml (Just (Y.YamlParseException _ _ mark)) -> Y.yamlLine mark
      _ -> 0
    yamlMessage = \case
      Y.InvalidYaml (Just (Y.YamlParseException problem ctx _)) ->
        "invalid YAML in the metadata: " <> T.pack problem <> (if null ctx then "" else " (" <> T.pack ctx <> ")")
      e -> "invalid YAML in the metadata: " <> T.pack (Y.prettyPrintParseException e)
    caseFromYaml :: Value -> V Case
    caseFromYaml v
      | iecDialect = iecCaseFromYaml v
      | otherwise = mastertoolCaseFromYaml v
    iecDialect = maybe False ((== IecController) . pModel) (lookupPreset (coDialect origin))
    mastertoolCaseFromYaml v = do
      o <- objectWith [] topKeys v
      (description, rules, features, status) <- header o
      kind <- optional o "module" (moduleOf ["module"]) ProcedureModule
      plc <- optional o "plc" (plcOf ["plc"]) (PlcSetup defaultPlcConfig [] Nothing)
      let cfg = psConfig plc
      calls <- optional o "calls" (callsOf cfg ["calls"]) [CallSetup (True, True, True) []]
      expect <- optional o "expect" (expectOf cfg ["expect"] expectKeys) emptyExpect
      conds <- optional o "expect-if" (conditionals cfg ["expect-if"]) []
      checkExpectations "code" expect conds
      pure (caseOf (description, rules, features, status) expect conds) {caseModule = kind, casePlc = plc, caseCalls = calls}

    -- a case from the keys every dialect has; MasterTool's controller
    -- defaults (module P, the default layout, all inputs TRUE), no IEC setup
    caseOf (description, rules, features, status) expect conds =
      Case
        { caseId = coId origin
        , caseFile = file
        , caseDialect = coDialect origin
        , caseArea = coArea origin
        , caseSource = src
        , caseDescription = description
        , caseRules = rules
        , caseFeatures = features
        , caseStatus = status
        , caseModule = ProcedureModule
        , casePlc = PlcSetup defaultPlcConfig [] Nothing
        , caseCalls = [CallSetup (True, True, True) []]
        , caseExpect = expect
        , caseExpectIf = conds
        , caseIec = Nothing
        }
    -- the keys every dialect's case has
    header o = do
      description <- required [] o "description" >>= text ["description"]
      rules <- required [] o "rules" >>= textList ["rules"]
      when (null rules) (failAt ["rules"] "a case must cite at least one rule")
      forM_' rules $ \r -> unless (knownRule r) (failAt ["rules"] ("rule " <> r <> " is not in the dialect's RULES index"))
      features <- optional o "features" (textList ["features"]) []
      status <- optional o "status" (statusOf ["status"]) Normative
      pure (description, rules, features, status)
    -- each verdict consistent; what an entry means once laid over expect: a
    -- runtime-error verdict must not inherit expect's @error: none@
    checkExpectations errorKey expect conds = do
      checkVerdict ["expect"] expect
      forM_' (zip [0 :: Int ..] conds) $ \(i, c) -> do
        checkVerdict ["expect-if", idx i] (cdExpect c)
        case mergeExpect expect (cdExpect c) of
          Expect {exVerdict = Just ExpRuntimeError, exError = Just ErrNone} ->
            failAt ["expect-if", idx i] ("verdict runtime-error, but the entry states no error and expect says error: none; state error: {" <> errorKey <> ": ...}")
          _ -> pure ()

    -- corpus-format §4.1: the IEC dialects' cases
    iecCaseFromYaml v = do
      o <- objectWith [] iecTopKeys v
      (description, rules, features, status) <- header o
      program <- optional o "program" (fmap Just . text ["program"]) Nothing
      cycleText <- optional o "cycle" (text ["cycle"]) "T#10ms"
      initial <- optional o "plc" (\x -> objectWith ["plc"] ["init"] x >>= \po -> optional po "init" (iecValues ["plc", "init"]) []) []
      calls <- optional o "calls" (iecCallsOf ["calls"]) [IecCall [] Nothing]
      expect <- optional o "expect" (iecExpectOf ["expect"] iecExpectKeys) emptyExpect
      conds <- optional o "expect-if" (iecConditionals ["expect-if"]) []
      checkExpectations "kind" expect conds
      pure (caseOf (description, rules, features, status) expect conds)
        { caseCalls = [CallSetup (True, True, True) [] | IecCall _ Nothing <- calls]
        , caseIec = Just (IecSetup program cycleText initial calls)
        }
    iecTopKeys = ["description", "rules", "features", "status", "program", "cycle", "plc", "calls", "expect", "expect-if"]
    iecExpectKeys = ["verdict", "vars", "operands", "error", "reject"]
    iecCallsOf p = \case
      Number n -> do
        k <- integerIn p 1 1000000 n
        pure (replicate (fromInteger k) (IecCall [] Nothing))
      Array xs
        | V.null xs -> failAt p "calls must list at least one cycle"
        | otherwise -> fmap concat . forM (zip [0 :: Int ..] (V.toList xs)) $ \(i, x) -> case x of
            Number n -> do
              k <- integerIn (p ++ [idx i]) 1 1000000 n
              pure (replicate (fromInteger k) (IecCall [] Nothing))
            _ -> do
              co <- objectWith (p ++ [idx i]) ["set", "reset"] x
              set <- optional co "set" (iecValues (p ++ [idx i, "set"])) []
              reset <- optional co "reset" (fmap Just . resetName (p ++ [idx i, "reset"])) Nothing
              case (set, reset) of
                (_ : _, Just _) -> failAt (p ++ [idx i]) "an entry either sets variables for a cycle or resets the controller, not both"
                _ -> pure [IecCall set reset]
      _ -> failAt p "calls must be a number of cycles or a list of numbers, {set: {...}} and {reset: warm|cold|origin|download}"
    resetName p = \case
      String t | t `elem` ["warm", "cold", "origin", "download"] -> pure t
      _ -> failAt p "a reset is warm, cold, origin or download"
    iecValues p v = do
      o <- object' p v
      forM (KM.toList o) (\(k, x) -> (K.toText k,) <$> iecValue (p ++ [K.toText k]) x)
    iecValue p = \case
      Bool b -> pure (EBool b)
      Number n -> case floatingOrInteger n :: Either Double Integer of
        Right i | base10Exponent n <= 40 -> pure (EInt i)
        _ -> pure (EDecimal n)
      String t
        | T.toLower t `elem` ["nan", ".nan"] -> pure ENaN
        | otherwise -> pure (EText t)
      Array xs -> EList <$> forM (zip [0 :: Int ..] (V.toList xs)) (\(i, x) -> iecValue (p ++ [idx i]) x)
      Object o
        | [(k, String t)] <- KM.toList o, k == "bits" -> maybe (failAt p ("bits must be a hexadecimal pattern like \"0x7F7FFFFF\", not '" <> t <> "'")) (pure . EBits) (parseBits t)
        | otherwise -> EMap . M.fromList <$> forM (KM.toList o) (\(k, x) -> (K.toText k,) <$> iecValue (p ++ [K.toText k]) x)
      _ -> failAt p "a value is a number, true/false, an ST literal in a string, a list or a mapping"
    iecExpectOf p keys v = do
      o <- objectWith p keys v
      verdict <- optional o "verdict" (fmap Just . verdictOf (p ++ ["verdict"])) Nothing
      vars <- optional o "vars" (fmap M.fromList . iecValues (p ++ ["vars"])) M.empty
      operands <- optional o "operands" (fmap M.fromList . iecValues (p ++ ["operands"])) M.empty
      err <- optional o "error" (fmap Just . iecErrorOf (p ++ ["error"])) Nothing
      rej <- optional o "reject" (fmap Just . rejectOf (p ++ ["reject"])) Nothing
      -- located variables are observed like variables, by their address
      pure (Expect verdict M.empty (M.union vars operands) M.empty err rej)
    iecErrorOf p = \case
      String "none" -> pure ErrNone
      v -> do
        o <- objectWith p ["kind", "line"] v
        k <- required p o "kind" >>= text (p ++ ["kind"])
        unless (k `elem` runtimeErrorKinds) (failAt (p ++ ["kind"]) ("'" <> k <> "' is not a runtime error kind: " <> T.intercalate ", " runtimeErrorKinds))
        line <- optional o "line" (fmap (Just . fromInteger) . (integerIn (p ++ ["line"]) 1 1000000 <=< number (p ++ ["line"]))) Nothing
        pure (ErrKind k line)
    iecConditionals p = \case
      Array xs -> forM (zip [0 :: Int ..] (V.toList xs)) $ \(i, x) -> do
        let q = p ++ [idx i]
        o <- objectWith q ("when" : iecExpectKeys) x
        whenV <- required q o "when" >>= whenOf (q ++ ["when"])
        e <- iecExpectOf q iecExpectKeys (Object (KM.delete "when" o))
        pure (Conditional whenV e)
      _ -> failAt p "expect-if must be a list of {when: {POLICY: CHOICE}, ...}"

    topKeys = ["description", "rules", "features", "status", "module", "plc", "calls", "expect", "expect-if"]
    expectKeys = ["verdict", "operands", "vars", "outputs", "error", "reject"]

    statusOf p v = text p v >>= \case
      "normative" -> pure Normative
      "policy" -> pure PolicyDependent
      "erratum" -> pure Erratum
      s -> failAt p ("status '" <> s <> "' is not one of normative, policy, erratum")
    moduleOf p v = text p v >>= \case
      "P" -> pure ProcedureModule
      "F" -> pure FunctionModule
      s -> failAt p ("module '" <> s <> "' is not P or F")

    plcOf p v = do
      o <- objectWith p ["declare", "diagnostics", "init", "chf"] v
      (simple, tables) <- optional o "declare" (declareOf (p ++ ["declare"])) (plcSimple defaultPlcConfig, plcTables defaultPlcConfig)
      diag <- optional o "diagnostics" (diagnosticsOf (p ++ ["diagnostics"])) (plcDiagnostics defaultPlcConfig)
      let cfg = PlcConfig simple tables diag
      initial <- optional o "init" (operandValues cfg (p ++ ["init"])) []
      chf <- optional o "chf" (fmap Just . chfOf (p ++ ["chf"])) Nothing
      pure (PlcSetup cfg initial chf)

    declareOf p v = do
      o <- objectWith p ["M", "E", "S", "A", "I", "F", "TM", "TI", "TF"] v
      simple <- forM [minBound .. maxBound] $ \k ->
        (k,) <$> optional o (simpleLetter k) (count (p ++ [simpleLetter k]) 65536) 0
      tables <- fmap concat . forM [minBound .. maxBound] $ \k ->
        optional o (tableLetters k) (tableDecl (p ++ [tableLetters k]) k) []
      pure (M.fromList [(k, n) | (k, n) <- simple, n > 0], M.fromList tables)
    tableDecl p k v = do
      o <- object' p v
      forM (KM.toList o) $ \(key, n) -> do
        let a = K.toText key
        unless (not (T.null a) && T.all isDigit a && T.length a <= 5) (failAt (p ++ [a]) ("table address '" <> a <> "' is not a number"))
        positions <- count (p ++ [a]) 65536 n
        pure ((k, read (T.unpack a)), positions)

    diagnosticsOf p v = do
      t <- text p v
      case parseOperand t of
        Right (OpSimple KM a) -> pure a
        Right _ -> failAt p ("the diagnostic band starts at a %M operand, not " <> t)
        Left e -> failAt p e

    chfOf p v = do
      o <- objectWith p ["in", "out"] v
      ins <- optional o "in" (textList (p ++ ["in"])) []
      outs <- optional o "out" (textList (p ++ ["out"])) []
      forM_' (ins ++ outs) $ \a -> either (failAt p) (const (pure ())) (parseChfArg a)
      pure (ins, outs)

    callsOf cfg p = \case
      Number n -> do
        k <- integerIn p 1 100000 n
        pure (replicate (fromInteger k) (CallSetup (True, True, True) []))
      Array xs
        | V.null xs -> failAt p "calls must list at least one call"
        | otherwise -> forM (zip [0 :: Int ..] (V.toList xs)) $ \(i, x) -> callOf cfg (p ++ [idx i]) x
      _ -> failAt p "calls must be a number or a list of {inputs, set}"
    callOf cfg p v = do
      o <- objectWith p ["inputs", "set"] v
      ins <- optional o "inputs" (boolList (p ++ ["inputs"])) [True, True, True]
      triple <- case ins of
        [a, b, c] -> pure (a, b, c)
        _ -> failAt (p ++ ["inputs"]) "inputs must list exactly three booleans (INPUT1, INPUT2, INPUT3)"
      set <- optional o "set" (operandValues cfg (p ++ ["set"])) []
      pure (CallSetup triple set)

    conditionals cfg p = \case
      Array xs -> forM (zip [0 :: Int ..] (V.toList xs)) $ \(i, x) -> do
        let q = p ++ [idx i]
        o <- objectWith q ("when" : expectKeys) x
        whenV <- required q o "when" >>= whenOf (q ++ ["when"])
        e <- expectOf cfg q expectKeys (Object (KM.delete "when" o))
        pure (Conditional whenV e)
      _ -> failAt p "expect-if must be a list of {when: {POLICY: CHOICE}, ...}"
    whenOf p v = do
      o <- object' p v
      when (KM.null o) (failAt p "when must name at least one policy")
      forM (KM.toList o) $ \(key, choiceV) -> do
        let name = K.toText key
            q = p ++ [name]
        choice <- scalarText q choiceV
        case lookupPolicy name of
          Nothing -> failAt q ("unknown policy '" <> name <> "'; the policies are: " <> T.intercalate ", " (map piName policyTable))
          Just info
            | not (null (piAlternatives info)) && choice `notElem` piAlternatives info ->
                failAt q ("policy " <> name <> " has no alternative '" <> choice <> "'; its alternatives are: " <> T.intercalate ", " (piAlternatives info))
            | otherwise -> pure (name, choice)

    expectOf cfg p keys v = do
      o <- objectWith p keys v
      verdict <- optional o "verdict" (fmap Just . verdictOf (p ++ ["verdict"])) Nothing
      operands <- M.fromList <$> optional o "operands" (operandValues cfg (p ++ ["operands"])) []
      vars <- optional o "vars" (varValues (p ++ ["vars"])) M.empty
      outputs <- optional o "outputs" (outputsOf (p ++ ["outputs"])) M.empty
      err <- optional o "error" (fmap Just . errorOf (p ++ ["error"])) Nothing
      rej <- optional o "reject" (fmap Just . rejectOf (p ++ ["reject"])) Nothing
      pure (Expect verdict operands vars outputs err rej)
    verdictOf p v = text p v >>= \case
      "ok" -> pure ExpOk
      "rejected" -> pure ExpRejected
      "runtime-error" -> pure ExpRuntimeError
      s -> failAt p ("verdict '" <> s <> "' is not one of ok, rejected, runtime-error")
    outputsOf p v = do
      o <- object' p v
      M.fromList <$> forM (KM.toList o) (\(key, b) -> do
        let name = K.toText key
        n <- case T.toUpper name of
          "OUTPUT1" -> pure 1
          "OUTPUT2" -> pure 2
          "OUTPUT3" -> pure 3
          _ -> failAt (p ++ [name]) ("'" <> name <> "' is not an output signal (OUTPUT1, OUTPUT2, OUTPUT3)")
        (n,) <$> bool (p ++ [name]) b)
    errorOf p = \case
      String "none" -> pure ErrNone
      v -> do
        o <- objectWith p ["code", "line", "comp"] v
        code <- required p o "code" >>= (integerIn (p ++ ["code"]) 0 65535 <=< number (p ++ ["code"]))
        line <- optional o "line" (fmap (Just . fromInteger) . (integerIn (p ++ ["line"]) (-32768) 32767 <=< number (p ++ ["line"]))) Nothing
        comp <- optional o "comp" (fmap Just . compOf (p ++ ["comp"])) Nothing
        pure (ErrCode (fromInteger code) line comp)
    compOf p = \case
      Array xs | [a, b, c] <- V.toList xs -> do
        x <- (integerIn p (-32768) 65535 <=< number p) a
        y <- (integerIn p (-32768) 65535 <=< number p) b
        z <- (integerIn p (-32768) 65535 <=< number p) c
        pure (fromInteger x, fromInteger y, fromInteger z)
      _ -> failAt p "comp must list three integers"
    rejectOf p v = do
      o <- objectWith p ["line", "kind"] v
      line <- optional o "line" (fmap (Just . fromInteger) . (integerIn (p ++ ["line"]) 1 1000000 <=< number (p ++ ["line"]))) Nothing
      kind <- optional o "kind" (fmap Just . text (p ++ ["kind"])) Nothing
      pure (ExpReject line kind)

    checkVerdict p e = case (exVerdict e, exReject e, exError e) of
      (Just v, Just _, _) | v /= ExpRejected -> failAt p "reject is stated but the verdict is not rejected"
      (Just ExpRejected, _, Just _) -> failAt p "a rejected program has no runtime error; drop error"
      (Just ExpOk, _, Just ErrCode {}) -> failAt p "verdict ok with an error code; the verdict of a call that raised an error is runtime-error"
      (Just ExpRuntimeError, _, Just ErrNone) -> failAt p "verdict runtime-error with error: none"
      _ -> pure ()

    -- operand → value maps, sorted so that whole words precede their bits
    operandValues cfg p v = do
      o <- object' p v
      pairs <- forM (KM.toList o) $ \(key, x) -> do
        let t = K.toText key
            q = p ++ [t]
        op <- either (failAt q) pure (parseOperand t)
        unless (cellDeclared cfg (operandCell op) || inDiagnosticBand cfg op) $
          failAt q ("operand " <> renderOperand op <> " does not exist in this case's PLC layout (see plc.declare)")
        ev <- valueOf q x
        checked <- fitOperand q op ev
        pure (op, checked)
      pure (sortOn fst pairs)
    varValues p v = do
      o <- object' p v
      M.fromList <$> forM (KM.toList o) (\(key, x) -> (K.toText key,) <$> valueOf (p ++ [K.toText key]) x)

    fitOperand p op ev = case (op, ev) of
      (OpBit {}, EBool _) -> pure ev
      (OpBit {}, _) -> failAt p ("the bit operand " <> renderOperand op <> " takes true or false")
      (_, EBool _) -> failAt p (renderOperand op <> " is not a bit; it takes a number")
      _ | operandIsReal op -> case ev of
            EInt n -> pure (EReal (fromInteger n))
            _ -> pure ev
      (_, EInt n)
        | n >= negate (2 ^ (w - 1)) && n < 2 ^ w -> pure ev
        | otherwise -> failAt p (T.pack (show n) <> " does not fit the " <> T.pack (show w) <> " bits of " <> renderOperand op)
      (_, EBits b)
        | toInteger b < 2 ^ w -> pure ev
        | otherwise -> failAt p ("the bit pattern does not fit the " <> T.pack (show w) <> " bits of " <> renderOperand op)
      _ -> failAt p (renderOperand op <> " is an integer operand; it takes an integer, not a REAL or nan")
      where
        w = operandBits op :: Int

    valueOf p = \case
      Bool b -> pure (EBool b)
      Number n -> case floatingOrInteger' n of
        Right i -> pure (EInt i)
        Left f -> pure (EReal f)
      String s
        | T.toLower s `elem` ["nan", ".nan"] -> pure ENaN
      Object o
        | [(k, String s)] <- KM.toList o, k == "bits" ->
            case parseBits s of
              Just w -> pure (EBits w)
              Nothing -> failAt p ("bits must be a hexadecimal pattern like \"0x7F7FFFFF\", not '" <> s <> "'")
      _ -> failAt p "a value is an integer, true/false, a decimal REAL, {bits: \"0x...\"} or nan"

    floatingOrInteger' :: Scientific -> Either Float Integer
    floatingOrInteger' n
      | base10Exponent n > 40 = Left (scientificToFloat n)
      | otherwise = case floatingOrInteger n :: Either Double Integer of
          Right i -> Right i
          Left _ -> Left (scientificToFloat n)

    -- generic helpers
    objectWith p allowed v = do
      o <- object' p v
      forM_' (KM.keys o) $ \k ->
        unless (K.toText k `elem` allowed) $
          failAt (p ++ [K.toText k]) ("unknown key '" <> K.toText k <> "'; the keys here are: " <> T.intercalate ", " allowed)
      pure o
    object' p = \case
      Object o -> pure o
      Null -> pure KM.empty
      _ -> failAt p "expected a mapping {key: value}"
    required p o k = maybe (failAt (p ++ [k]) ("the key '" <> k <> "' is required")) pure (KM.lookup (K.fromText k) o)
    optional o k f d = maybe (pure d) f (KM.lookup (K.fromText k) o)
    text p = \case
      String s -> pure s
      _ -> failAt p "expected a text"
    scalarText p = \case
      String s -> pure s
      Number n -> pure (T.pack (either (show :: Double -> String) (show :: Integer -> String) (floatingOrInteger n)))
      Bool b -> pure (if b then "true" else "false")
      _ -> failAt p "expected a policy choice"
    textList p = \case
      Array xs -> forM (V.toList xs) (text p)
      String s -> pure [s]
      _ -> failAt p "expected a list [a, b]"
    boolList p = \case
      Array xs -> forM (V.toList xs) (bool p)
      _ -> failAt p "expected a list of true/false"
    bool p = \case
      Bool b -> pure b
      _ -> failAt p "expected true or false"
    number p = \case
      Number n -> pure n
      _ -> failAt p "expected a number"
    count p hi v = fromInteger <$> (number p v >>= integerIn p 0 hi)
    integerIn :: Path -> Integer -> Integer -> Scientific -> V Integer
    integerIn p lo hi n
      | base10Exponent n > 12 = failAt p "number out of range"
      | otherwise = case floatingOrInteger n :: Either Double Integer of
          Right i | i >= lo && i <= hi -> pure i
          Right i -> failAt p (T.pack (show i) <> " is outside " <> T.pack (show lo) <> ".." <> T.pack (show hi))
          Left _ -> failAt p "expected an integer"
    idx i = "[" <> T.pack (show i) <> "]"
    forM_' xs f = mapM_ f xs

-- | The runtime error kinds of corpus-format §4.3.
runtimeErrorKinds :: [Text]
runtimeErrorKinds = ["division-by-zero", "index-out-of-range", "subrange", "overflow", "null-pointer", "conversion", "watchdog", "call-depth"]

-- | @expect.operands.%M0012: @ for messages.
describePath :: Path -> Text
describePath [] = ""
describePath (k : ks) = k <> T.concat [if "[" `T.isPrefixOf` x then x else "." <> x | x <- ks] <> ": "

-- | The 0-based line (of the metadata text) where a path's last key is
-- written: each key is looked for from the line of its parent on, so that
-- @expect.operands.%M0012@ finds the %M0012 below @expect:@. List positions
-- do not move the search.
locate :: [Text] -> Path -> Int
locate ls = go 0
  where
    go cur [] = cur
    go cur (k : ks)
      | "[" `T.isPrefixOf` k = go cur ks
      | otherwise = case [i | (i, l) <- drop cur (zip [0 ..] ls), keyOn k l] of
          (i : _) -> go i ks
          [] -> cur
    keyOn k l = any (`T.isInfixOf` l) [k <> ":", k <> "\":", k <> "':"]
