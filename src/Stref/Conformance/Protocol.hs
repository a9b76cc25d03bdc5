-- | The engine protocol @stref-engine/1@ (conformance/README.md, "Engines: the
-- protocol"): one JSON request on an engine's standard input,
-- one JSON answer on its standard output.
--
-- The runner always sends a complete request: the full policy assignment,
-- the resolved PLC layout (never an empty @declare@), one entry per call.
-- Decoding is lenient about fields it does not know, so that a later minor
-- extension does not break an engine.
module Stref.Conformance.Protocol
  ( protocolVersion
  -- * Values
  , Scalar (..)
  , scalarFromFloat
  , scalarToFloat
  , scientificToFloat
  , smallInteger
  , parseBits
  , bitsText
  -- * Requests
  , Request (..)
  , PlcRequest (..)
  , Declare (..)
  , declareFromConfig
  , declareToConfig
  , ChfRequest (..)
  , CallRequest (..)
  , Observe (..)
  -- * Answers
  , Answer (..)
  , RunVerdict (..)
  , Observation (..)
  , emptyObservation
  , ErrorReport (..)
  , encodeAnswer
  , decodeAnswer
  , encodeRequest
  , decodeRequest
  ) where

import Data.Aeson
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import Data.Aeson.Types (Parser)
import qualified Data.ByteString.Lazy as BL
import Data.Char (isHexDigit)
import Data.Map.Strict (Map)
import qualified Data.Map.Strict as M
import Data.Scientific (Scientific, base10Exponent, coefficient, floatingOrInteger, fromFloatDigits)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word32)
import Numeric (readHex, showHex)
import Stref.Operands (PlcConfig (..), SimpleKind (..), TableKind (..), simpleLetter, tableLetters)
import Stref.Values (realBits, realFromBits)
import Text.Read (readMaybe)

protocolVersion :: Text
protocolVersion = "stref-engine/1"

-- | A value of an operand or a variable, as JSON carries it: a number
-- (integer or decimal), a boolean, an exact bit pattern @{"bits": "0x…"}@, or
-- the string @"nan"@ (any NaN).
data Scalar
  = SNumber Scientific
  | SBool Bool
  | SBits Word32
  | SNaN
  | SText Text -- ^ an ST literal of the dialect (corpus-format §4.2): @"T#1s"@, @"'abc'"@, @"green"@
  | SList [Scalar] -- ^ a whole array, element by element
  | SMap (Map Text Scalar) -- ^ a whole structure, field by field
  deriving (Eq, Show)

instance ToJSON Scalar where
  toJSON = \case
    SNumber n -> Number n
    SBool b -> Bool b
    SBits w -> object ["bits" .= bitsText w]
    SNaN -> String "nan"
    SText t -> String t
    SList xs -> toJSON xs
    SMap m -> toJSON m

instance FromJSON Scalar where
  parseJSON = \case
    Number n -> pure (SNumber n)
    Bool b -> pure (SBool b)
    String s | T.toLower s `elem` ["nan", ".nan"] -> pure SNaN
    Object o | [(k, String s)] <- KM.toList o, k == "bits" ->
      maybe (fail ("bits must be a hexadecimal pattern like \"0x7F7FFFFF\", not " <> show s)) (pure . SBits) (parseBits s)
    String s -> pure (SText s)
    Array xs -> SList <$> traverse parseJSON (foldr (:) [] xs)
    Object o -> SMap . M.fromList <$> traverse (\(k, v) -> (K.toText k,) <$> parseJSON v) (KM.toList o)
    v -> fail ("expected a number, true/false, {\"bits\": \"0x...\"} or \"nan\", got " <> take 60 (show v))

-- | @0x7F7FFFFF@: eight upper-case hexadecimal digits.
bitsText :: Word32 -> Text
bitsText w = let h = showHex w "" in T.pack ("0x" ++ replicate (8 - length h) '0' ++ map toUpperHex h)
  where
    toUpperHex c = if c >= 'a' && c <= 'f' then toEnum (fromEnum c - 32) else c

-- | @0x…@ with one to eight hexadecimal digits.
parseBits :: Text -> Maybe Word32
parseBits s = case T.unpack (T.toLower s) of
  '0' : 'x' : ds
    | not (null ds), length ds <= 8, all isHexDigit ds, [(n, "")] <- readHex ds -> Just (fromInteger n)
  _ -> Nothing

-- | A binary32 as JSON: finite values (except -0.0) as the shortest decimal
-- that reads back to the same binary32; -0.0, infinities and NaNs as bits.
scalarFromFloat :: Float -> Scalar
scalarFromFloat f
  | isNaN f || isInfinite f || isNegativeZero f = SBits (realBits f)
  | otherwise = SNumber (fromFloatDigits f)

-- | The binary32 a scalar denotes (numbers round to nearest, ties to even).
scalarToFloat :: Scalar -> Maybe Float
scalarToFloat = \case
  SNumber n -> Just (scientificToFloat n)
  SBits w -> Just (realFromBits w)
  SNaN -> Just (0 / 0)
  _ -> Nothing

-- | Correctly rounded: the exact decimal as a 'Rational', then GHC's
-- correctly rounded 'fromRational'. Exponents far outside binary32's range
-- are decided without building huge rationals (a hostile answer could send
-- @1e1000000000@).
scientificToFloat :: Scientific -> Float
scientificToFloat n
  | coefficient n == 0 = 0
  | base10Exponent n + digits > 60 = if coefficient n > 0 then 1 / 0 else -1 / 0
  | base10Exponent n + digits < -60 = if coefficient n > 0 then 0 else -0.0
  | otherwise = fromRational (toRational n)
  where
    digits = length (show (abs (coefficient n)))

-- | The integer a number denotes, if it is one of at most 40 digits (so that
-- an answer such as @1e1000000000@ cannot make the runner build a huge
-- integer).
smallInteger :: Scientific -> Maybe Integer
smallInteger n
  | base10Exponent n > 40 = Nothing
  | otherwise = case floatingOrInteger n :: Either Double Integer of
      Right i | abs i < 10 ^ (40 :: Int) -> Just i
      _ -> Nothing

-- | Which operands the controller declares: counts of simple operands and
-- positions of each table (@TM@ address → positions).
data Declare = Declare
  { dSimple :: Map SimpleKind Int
  , dTables :: Map (TableKind, Int) Int
  }
  deriving (Eq, Show)

declareFromConfig :: PlcConfig -> Declare
declareFromConfig c = Declare (plcSimple c) (plcTables c)

-- | The configuration with the diagnostic band at @%M<diag>@.
declareToConfig :: Int -> Declare -> PlcConfig
declareToConfig diag (Declare s t) = PlcConfig s t diag

instance ToJSON Declare where
  toJSON (Declare s t) =
    object $
      [K.fromText (simpleLetter k) .= n | (k, n) <- M.toList s]
        ++ [ K.fromText (tableLetters k) .= object [K.fromText (T.pack (show a)) .= n | ((k', a), n) <- M.toList t, k' == k]
           | k <- [minBound .. maxBound]
           ]

instance FromJSON Declare where
  parseJSON = withObject "declare" $ \o -> do
    let entries = KM.toList o
    simple <- fmap concat . traverse simpleEntry $ entries
    tables <- fmap concat . traverse tableEntry $ entries
    pure (Declare (M.fromList simple) (M.fromList tables))
    where
      simpleKinds = [(simpleLetter k, k) | k <- [minBound .. maxBound]]
      tableKinds = [(tableLetters k, k) | k <- [minBound .. maxBound]]
      simpleEntry (key, v) = case lookup (K.toText key) simpleKinds of
        Just k -> (\n -> [(k, n)]) <$> parseJSON v
        Nothing
          | Just _ <- lookup (K.toText key) tableKinds -> pure []
          | otherwise -> fail ("unknown operand kind " <> show (K.toText key) <> " in declare")
      tableEntry (key, v) = case lookup (K.toText key) tableKinds of
        Nothing -> pure []
        Just k -> withObject "tables" (traverse (tablePos k) . KM.toList) v
      tablePos k (addr, v) = case readMaybe (T.unpack (K.toText addr)) of
        Just a -> (\n -> ((k, a), n)) <$> parseJSON v
        Nothing -> fail ("table address " <> show (K.toText addr) <> " is not a number")

-- | Parameters of the CHF instruction (F modules), as the case writes them.
data ChfRequest = ChfRequest {chfIn :: [Text], chfOut :: [Text]}
  deriving (Eq, Show)

instance ToJSON ChfRequest where
  toJSON (ChfRequest i o) = object ["in" .= i, "out" .= o]

instance FromJSON ChfRequest where
  parseJSON = withObject "chf" $ \o -> ChfRequest <$> o .:? "in" .!= [] <*> o .:? "out" .!= []

data PlcRequest = PlcRequest
  { prDeclare :: Declare
  , prDiagnostics :: Text -- ^ the first diagnostic operand, e.g. @%M1990@
  , prInit :: Map Text Scalar
  -- ^ applied in the order of the operands (whole words before their bits)
  , prChf :: Maybe ChfRequest
  }
  deriving (Eq, Show)

instance ToJSON PlcRequest where
  toJSON p = object ["declare" .= prDeclare p, "diagnostics" .= prDiagnostics p, "init" .= prInit p, "chf" .= prChf p]

instance FromJSON PlcRequest where
  parseJSON = withObject "plc" $ \o ->
    PlcRequest <$> o .: "declare" <*> o .: "diagnostics" <*> o .:? "init" .!= M.empty <*> o .:? "chf"

-- | One module call: INPUT1..3 and the operands written just before it.
data CallRequest = CallRequest
  { callInputs :: (Bool, Bool, Bool)
  , callSet :: Map Text Scalar
  , callReset :: Maybe Text
  -- ^ IEC dialects: instead of a cycle, a reset of the controller
  -- (@warm@, @cold@, @origin@, @download@; docs/nexto.md)
  }
  deriving (Eq, Show)

instance ToJSON CallRequest where
  toJSON (CallRequest (a, b, c) s r) = object (["inputs" .= [a, b, c], "set" .= s] ++ maybe [] (\x -> ["reset" .= x]) r)

instance FromJSON CallRequest where
  parseJSON = withObject "call" $ \o -> do
    ins <- o .:? "inputs" .!= [True, True, True]
    triple <- case ins of
      [a, b, c] -> pure (a, b, c)
      _ -> fail "inputs must list exactly three booleans (INPUT1..3)"
    CallRequest triple <$> o .:? "set" .!= M.empty <*> o .:? "reset"

-- | What the runner will compare: the engine reports at least these.
data Observe = Observe
  { obsOperands :: [Text]
  , obsVars :: [Text]
  , obsOutputs :: [Text]
  , obsError :: Bool
  }
  deriving (Eq, Show)

instance ToJSON Observe where
  toJSON (Observe o v u e) = object ["operands" .= o, "vars" .= v, "outputs" .= u, "error" .= e]

instance FromJSON Observe where
  parseJSON = withObject "observe" $ \o ->
    Observe <$> o .:? "operands" .!= [] <*> o .:? "vars" .!= [] <*> o .:? "outputs" .!= [] <*> o .:? "error" .!= True

data Request = Request
  { rqProtocol :: Text
  , rqCase :: Text -- ^ the case id, e.g. @mastertool-xe/arith/int-add-saturates@
  , rqDialect :: Text
  , rqPolicies :: Map Text Text -- ^ policy name → alternative (the whole table)
  , rqSource :: Text -- ^ the whole case file
  , rqModule :: Text -- ^ @P@ or @F@
  , rqPlc :: PlcRequest
  , rqCalls :: [CallRequest]
  , rqObserve :: Observe
  , rqProgram :: Maybe Text -- ^ IEC dialects (§4.4): the PROGRAM to run, when the case names one
  , rqCycle :: Maybe Text -- ^ IEC dialects: the task interval as a TIME literal
  }
  deriving (Eq, Show)

instance ToJSON Request where
  toJSON r =
    object $
      [ "protocol" .= rqProtocol r
      , "case" .= rqCase r
      , "dialect" .= rqDialect r
      , "policies" .= rqPolicies r
      , "source" .= rqSource r
      , "module" .= rqModule r
      , "plc" .= rqPlc r
      , "calls" .= rqCalls r
      , "observe" .= rqObserve r
      ]
        ++ maybe [] (\p -> ["program" .= p]) (rqProgram r)
        ++ maybe [] (\c -> ["cycle" .= c]) (rqCycle r)

instance FromJSON Request where
  parseJSON = withObject "request" $ \o ->
    Request
      <$> o .: "protocol"
      <*> o .:? "case" .!= ""
      <*> o .: "dialect"
      <*> o .:? "policies" .!= M.empty
      <*> o .: "source"
      <*> o .:? "module" .!= "P"
      <*> o .: "plc"
      <*> o .:? "calls" .!= [CallRequest (True, True, True) M.empty Nothing]
      <*> o .:? "observe" .!= Observe [] [] [] True
      <*> o .:? "program"
      <*> o .:? "cycle"

-- | A runtime error as reported: MasterTool's code and three complements,
-- or an IEC dialect's kind (corpus-format §4.3); the line.
data ErrorReport = ErrorReport
  { erCode :: Maybe Int
  , erKind :: Maybe Text
  , erLine :: Maybe Int
  , erComp :: Maybe (Int, Int, Int)
  }
  deriving (Eq, Show)

instance ToJSON ErrorReport where
  toJSON (ErrorReport c k l comp) =
    object (maybe [] (\x -> ["code" .= x]) c ++ maybe [] (\x -> ["kind" .= x]) k ++ maybe [] (\x -> ["line" .= x]) l ++ maybe [] (\(a, b, d) -> ["comp" .= [a, b, d]]) comp)

instance FromJSON ErrorReport where
  parseJSON = withObject "error" $ \o -> do
    comp <- o .:? "comp"
    c3 <- case comp of
      Nothing -> pure Nothing
      Just [a, b, d] -> pure (Just (a, b, d))
      Just _ -> fail "comp must list three integers"
    code <- o .:? "code"
    kind <- o .:? "kind"
    case (code, kind) of
      (Nothing, Nothing) -> fail "an error states a code (MasterTool) or a kind (IEC dialects)"
      _ -> ErrorReport code kind <$> o .:? "line" <*> pure c3

-- | What an engine observed after the last call.
data Observation = Observation
  { obOperands :: Map Text Scalar
  , obVars :: Map Text Scalar
  , obOutputs :: Map Text Bool
  , obError :: Maybe ErrorReport -- ^ 'Nothing': the last call ended without error
  }
  deriving (Eq, Show)

emptyObservation :: Observation
emptyObservation = Observation M.empty M.empty M.empty Nothing

data RunVerdict = VerdictOk | VerdictRuntimeError
  deriving (Eq, Show)

data Answer
  = AnswerRun RunVerdict Observation -- ^ @ok@ or @runtime-error@
  | AnswerRejected (Maybe Int) (Maybe Text) Text
  -- ^ line, the project's error kind (an extension; other engines may omit
  -- it), message
  | AnswerUnsupported Text
  deriving (Eq, Show)

instance ToJSON Answer where
  toJSON = \case
    AnswerRun v ob ->
      object
        [ "verdict" .= (case v of VerdictOk -> "ok" :: Text; VerdictRuntimeError -> "runtime-error")
        , "operands" .= obOperands ob
        , "vars" .= obVars ob
        , "outputs" .= obOutputs ob
        , "error" .= obError ob
        ]
    AnswerRejected l k m ->
      object (["verdict" .= ("rejected" :: Text), "message" .= m] ++ maybe [] (\x -> ["line" .= x]) l ++ maybe [] (\x -> ["kind" .= x]) k)
    AnswerUnsupported r -> object ["verdict" .= ("unsupported" :: Text), "reason" .= r]

instance FromJSON Answer where
  parseJSON = withObject "answer" $ \o -> do
    verdict <- o .: "verdict" :: Parser Text
    case verdict of
      "ok" -> AnswerRun VerdictOk <$> observation o
      "runtime-error" -> AnswerRun VerdictRuntimeError <$> observation o
      "rejected" -> AnswerRejected <$> o .:? "line" <*> o .:? "kind" <*> o .:? "message" .!= ""
      "unsupported" -> AnswerUnsupported <$> o .:? "reason" .!= ""
      _ -> fail ("unknown verdict " <> show verdict <> " (ok, runtime-error, rejected, unsupported)")
    where
      observation o =
        Observation
          <$> o .:? "operands" .!= M.empty
          <*> o .:? "vars" .!= M.empty
          <*> o .:? "outputs" .!= M.empty
          <*> o .:? "error"

encodeAnswer :: Answer -> BL.ByteString
encodeAnswer = encode

decodeAnswer :: BL.ByteString -> Either String Answer
decodeAnswer = eitherDecode

encodeRequest :: Request -> BL.ByteString
encodeRequest = encode

decodeRequest :: BL.ByteString -> Either String Request
decodeRequest = eitherDecode

