-- | CODESYS's conditional compilation (catalogue §1.5, NX-PRAGMA-13..16;
-- manual L4680-5160), as a pass over the source text before the parser.
--
-- 'preprocess' replaces every conditional-compilation pragma (@{define}@,
-- @{undefine}@, @{IF}@, @{ELSIF}@, @{ELSE}@, @{END_IF}@) and every region
-- that an @{IF}@ leaves out by spaces, keeping newlines, carriage returns
-- and tabs, so that each line and column of the text that remains is the
-- same as in the source. Every other pragma (@{attribute ...}@, the
-- message pragmas, unknown ones) stays for the parser.
--
-- Decisions and simplifications (docs/nexto.md, "Conditional compilation"):
--
-- * A define lasts from its position to the end of the top-level object
--   that contains it (NX-PRAGMA-3): a POU (with its methods, properties and
--   actions, and with its declaration part and body together), a TYPE
--   block, a top-level VAR_GLOBAL block (a GVL), a CONFIGURATION. A define
--   written between two objects belongs to the next one.
-- * Define names are case-insensitive; @{define id 'text'}@ and
--   @{define id text}@ both give the value @text@; a define is never
--   substituted into the program text.
-- * The declaration queries read the declarations of the whole source as
--   written, including regions that an @{IF}@ leaves out.
-- * @defined(variable:v)@, @hasattribute(variable:...)@ and
--   @hastype(variable:...)@ look for @v@ in the POUs that contain the
--   pragma (innermost first, then the function blocks they EXTEND), then
--   in the GVLs.
module Stref.IEC.Pragma
  ( preprocess
  , preprocessWith
  ) where

import Data.Char (isAsciiLower, isAsciiUpper, isDigit, isSpace)
import Data.List (sortOn)
import qualified Data.Map.Strict as Map
import Data.Maybe (isJust, listToMaybe)
import Data.Ord (Down (..))
import qualified Data.Set as Set
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Policy (NestedComments (..))
import Stref.Syntax (Pos (..))
import Stref.Verification (VerificationError (..))

-- | The source with the conditional-compilation pragmas and the regions
-- they leave out turned into spaces (NX-PRAGMA-13), comments nesting as in
-- CODESYS (NX-LEX-17). Errors have the kind @pragma-syntax@.
preprocess :: Text -> Either VerificationError Text
preprocess = preprocessWith Nesting

-- | 'preprocess' with the comment nesting of the policy @nested-comments@.
preprocessWith :: NestedComments -> Text -> Either VerificationError Text
preprocessWith nest src =
  let str = T.unpack src
      toks = lexTokens nest str
      decls = scanDecls (zip (tokenLines str toks) toks)
   in case walk decls toks of
        Left (off, msg) -> Left (VerificationError "pragma-syntax" (posAt src off) msg)
        Right blanks -> Right (render src blanks)

posAt :: Text -> Int -> Pos
posAt src off =
  let before = T.take off src
   in Pos (1 + T.count "\n" before) (1 + T.length (T.takeWhileEnd (/= '\n') before))

-- | The text with each interval (start, end) of offsets blanked; the
-- intervals come in increasing order and may touch or overlap.
render :: Text -> [(Int, Int)] -> Text
render src = T.concat . go 0 src
  where
    go cur rest = \case
      [] -> [rest]
      (s, e) : more
        | e <= cur -> go cur rest more
        | otherwise ->
            let s' = max s cur
                (keep, r1) = T.splitAt (s' - cur) rest
                (gone, r2) = T.splitAt (e - s') r1
             in keep : T.map blank gone : go e r2 more
    blank c = if c == '\n' || c == '\r' || c == '\t' then c else ' '

------------------------------------------------------------------------------
-- Tokens

data Tok = Tok {tStart :: !Int, tEnd :: !Int, tVal :: !TokVal}

data TokVal
  = TWord !Text -- ^ a name or keyword, in upper case
  | TSym !Char
  | TPragma !Int !Text -- ^ offset of the text inside the braces, and that text
  | TLit -- ^ a number, string or direct address

isWordChar :: Char -> Bool
isWordChar c = isAsciiUpper c || isAsciiLower c || isDigit c || c == '_'

isNameStart :: Char -> Bool
isNameStart c = isAsciiUpper c || isAsciiLower c || c == '_'

-- | The tokens outside comments and strings (NX-LEX-14, NX-LEX-15,
-- NX-LEX-17). A pragma is a brace with its closing brace on the same line
-- (NX-PRAGMA-1); braces in quotes inside it do not close it. A string not
-- closed on its line ends there (the parser reports it).
lexTokens :: NestedComments -> String -> [Tok]
lexTokens nest = go 0
  where
    go :: Int -> String -> [Tok]
    go !o s = case s of
      [] -> []
      '(' : '*' : r -> comment (o + 2) (1 :: Int) r
      '/' : '/' : r -> let (a, b) = break (== '\n') r in go (o + 2 + length a) b
      q : r | q == '\'' || q == '"' -> str o q (o + 1) r
      -- := is one token, never taken for the colon of a declaration
      ':' : '=' : r -> Tok o (o + 2) (TSym '=') : go (o + 2) r
      '{' : r -> case pragmaLength r of
        Just n -> Tok o (o + n + 2) (TPragma (o + 1) (T.pack (take n r))) : go (o + n + 2) (drop (n + 1) r)
        Nothing -> Tok o (o + 1) (TSym '{') : go (o + 1) r
      '%' : r -> let (a, b) = span (\c -> isWordChar c || c == '.' || c == '*') r in Tok o (o + 1 + length a) TLit : go (o + 1 + length a) b
      c : r
        | isSpace c -> go (o + 1) r
        | isNameStart c -> let (a, b) = span isWordChar s in Tok o (o + length a) (TWord (T.toUpper (T.pack a))) : go (o + length a) b
        | isDigit c -> let (a, b) = span isWordChar s in Tok o (o + length a) TLit : go (o + length a) b
        | otherwise -> Tok o (o + 1) (TSym c) : go (o + 1) r
    comment !o !d s = case s of
      [] -> []
      '*' : ')' : r -> if d == 1 then go (o + 2) r else comment (o + 2) (d - 1) r
      '(' : '*' : r | nest == Nesting -> comment (o + 2) (d + 1) r
      _ : r -> comment (o + 1) d r
    str start q !o s = case s of
      [] -> [Tok start o TLit]
      '\n' : _ -> Tok start o TLit : go o s
      '$' : c : r | c /= '\n' -> str start q (o + 2) r
      c : r | c == q -> Tok start (o + 1) TLit : go (o + 1) r
      _ : r -> str start q (o + 1) r

-- | The line of each token.
tokenLines :: String -> [Tok] -> [Int]
tokenLines = go 1 0
  where
    go !line !o s = \case
      [] -> []
      t : ts ->
        let (skipped, s') = splitAt (tStart t - o) s
            line' = line + length (filter (== '\n') skipped)
         in line' : go line' (tStart t) s' ts

-- | The length of a pragma's text up to its closing brace on the same line.
pragmaLength :: String -> Maybe Int
pragmaLength = go 0
  where
    go !n = \case
      [] -> Nothing
      '\n' : _ -> Nothing
      '}' : _ -> Just n
      q : r | q == '\'' || q == '"' -> inQuote q (n + 1) r
      _ : r -> go (n + 1) r
    inQuote q !n = \case
      [] -> Nothing
      '\n' : _ -> Nothing
      '$' : c : r | c /= '\n' -> inQuote q (n + 2) r
      c : r | c == q -> go (n + 1) r
      _ : r -> inQuote q (n + 1) r

------------------------------------------------------------------------------
-- The declarations the queries read

data Var = Var {vName :: !Text, vType :: !Text, vAttrs :: ![Text]}

data Pou = Pou
  { pName :: !Text
  , pQual :: !Text -- ^ @FB.M@ for a method M of FB, else the name
  , pAttrs :: ![Text]
  , pExtends :: !(Maybe Text)
  , pStart :: !Int
  , pEnd :: !Int
  , pVars :: ![Var]
  }

data Decls = Decls {dPous :: ![Pou], dGlobals :: ![Var], dTypes :: !(Set.Set Text)}

data Event
  = EPou !Int !Text !(Maybe Int) ![Text] !(Maybe Text) !Int !Int -- ^ id, name, enclosing POU, attributes, EXTENDS, start, line
  | EPouEnd !Int !Int
  | EVar !(Maybe Int) !Var !Int -- ^ the POU that declares it (none for a GVL), the line of its first name
  | EType !Text
  | EAttrLine !Int !Text -- ^ an attribute on a line with code: it is that line's (NX-PRAGMA-5)

data Ctx
  = CPou !Int !Text !Text -- ^ id, name, its closing keyword
  | CVars !(Maybe Int) !DState
  | CType !TState
  | CConfig
  | CSkip !Text -- ^ skipped up to this closing keyword

-- | The names so far, the attributes before them, the line of the first.
data DState = DStart ![Text] ![Text] !Int | DAt ![Text] ![Text] !Int | DType ![Text] ![Text] !Int | DSkip

data TState = TState {tsDepth :: !Int, tsParen :: !Int, tsSep :: !Bool}

closerOf :: Ctx -> Text
closerOf = \case
  CPou _ _ c -> c
  CVars _ _ -> "END_VAR"
  CType _ -> "END_TYPE"
  CConfig -> "END_CONFIGURATION"
  CSkip c -> c

pouKeywords :: Map.Map Text Text
pouKeywords =
  Map.fromList
    [ ("PROGRAM", "END_PROGRAM")
    , ("FUNCTION", "END_FUNCTION")
    , ("FUNCTION_BLOCK", "END_FUNCTION_BLOCK")
    , ("METHOD", "END_METHOD")
    , ("ACTION", "END_ACTION")
    , ("PROPERTY", "END_PROPERTY")
    ]

varKeywords :: Set.Set Text
varKeywords = Set.fromList ["VAR", "VAR_INPUT", "VAR_OUTPUT", "VAR_IN_OUT", "VAR_GLOBAL", "VAR_EXTERNAL", "VAR_TEMP", "VAR_STAT", "VAR_INST"]

-- | The attribute a pragma gives, @{attribute 'name'}@ or
-- @{attribute 'name' := 'value'}@ (NX-PRAGMA-5), in upper case.
attributeName :: Text -> Maybe Text
attributeName inner =
  let (kw, rest) = T.span isWordChar (T.stripStart inner)
   in if T.toUpper kw /= "ATTRIBUTE" then Nothing else fmap (T.toUpper . fst) (quoted (T.stripStart rest))

-- | A quoted string at the start of the text: its contents and what follows.
quoted :: Text -> Maybe (Text, Text)
quoted t = case T.uncons t of
  Just (q, r) | q == '\'' || q == '"' -> go q [] r
  _ -> Nothing
  where
    go q acc r = case T.uncons r of
      Nothing -> Nothing
      Just ('$', r') | Just (c, r'') <- T.uncons r' -> go q (c : acc) r''
      Just (c, r') | c == q -> Just (T.pack (reverse acc), r')
      Just (c, r') -> go q (c : acc) r'

-- | A light lexical scan for the declaration queries (NX-PRAGMA-15): POUs
-- with their attributes and variables, GVL variables, type names. It reads
-- every token, including those of regions an @{IF}@ leaves out. An
-- attribute is "valid for the current line, or the next one when it stands
-- on a line of its own" (manual L3954-3955): one on a line with code
-- belongs to what that line declares, one on a line of its own to the next
-- declaration.
scanDecls :: [(Int, Tok)] -> Decls
scanDecls toks = assemble (go [] [] 0 toks)
  where
    codeLines = Set.fromList [l | (l, t) <- toks, not (isPragma (tVal t))]
    isPragma = \case
      TPragma _ _ -> True
      _ -> False
    go :: [Ctx] -> [Text] -> Int -> [(Int, Tok)] -> [Event]
    go _ _ _ [] = []
    go ctx pending next ((line, t) : rest) = case tVal t of
      TPragma _ inner -> case attributeName inner of
        Nothing -> go ctx pending next rest
        Just a
          | line `Set.member` codeLines -> EAttrLine line a : go ctx pending next rest
          | otherwise -> go ctx (pending ++ [a]) next rest
      TWord w
        | any ((== w) . closerOf) ctx ->
            let (popped, kept) = break ((== w) . closerOf) ctx
                ends = [EPouEnd i (tEnd t) | CPou i _ _ <- popped ++ take 1 kept]
             in ends ++ go (drop 1 kept) [] next rest
      _ -> case ctx of
        [] -> topLevel
        CPou {} : _ -> topLevel
        CConfig : _ -> case tVal t of
          TWord w | w == "VAR_GLOBAL" -> go (CVars Nothing start : ctx) [] next rest
          _ -> go ctx [] next rest
        CSkip _ : _ -> go ctx [] next rest
        CVars owner st : more ->
          let (evs, st') = varStep owner pending line st (tVal t)
           in evs ++ go (CVars owner st' : more) [] next rest
        CType st : more ->
          let (evs, st') = typeStep st (tVal t) (map snd rest)
           in evs ++ go (CType st' : more) [] next rest
      where
        enclosing = listToMaybe [(i, n) | CPou i n _ <- ctx]
        start = DStart [] [] 0
        topLevel = case tVal t of
          TWord w
            | Just closer <- Map.lookup w pouKeywords
            , TWord name : after <- map (tVal . snd) rest ->
                let ext = case after of
                      TWord "EXTENDS" : TWord b : _ -> Just b
                      _ -> Nothing
                    qual = maybe name (\(_, n) -> n <> "." <> name) enclosing
                 in EPou next qual (fst <$> enclosing) pending ext (tStart t) line
                      : go (CPou next name closer : ctx) [] (next + 1) rest
            | w == "TYPE" -> go (CType (TState 0 0 True) : ctx) [] next rest
            | w == "INTERFACE" -> go (CSkip "END_INTERFACE" : ctx) [] next rest
            | w == "CONFIGURATION" -> go (CConfig : ctx) [] next rest
            | w == "VAR_CONFIG" || w == "VAR_ACCESS" -> go (CSkip "END_VAR" : ctx) [] next rest
            | w `Set.member` varKeywords -> go (CVars (fst <$> enclosing) start : ctx) [] next rest
          _ -> go ctx [] next rest

    -- one token of a VAR block: @a, b AT %IX0.0 : T := init;@
    varStep :: Maybe Int -> [Text] -> Int -> DState -> TokVal -> ([Event], DState)
    varStep owner pending line st tv = case (st, tv) of
      (DStart [] _ _, TWord w) | w `elem` ["CONSTANT", "RETAIN", "PERSISTENT", "NON_RETAIN"] -> ([], fresh)
      (DStart ns as l, TWord "AT") -> ([], DAt ns as l)
      (DStart [] _ _, TWord w) -> ([], DStart [w] pending line)
      (DStart ns as l, TWord w) -> ([], DStart (w : ns) as l)
      (DStart {}, TSym ',') -> ([], st)
      (DStart [] _ _, TSym ':') -> ([], DSkip)
      (DStart ns as l, TSym ':') -> ([], DType ns as l)
      (_, TSym ';') | not (isType st) -> ([], fresh)
      (DStart {}, _) -> ([], DSkip)
      (DAt ns as l, TSym ':') -> ([], DType ns as l)
      (DAt {}, _) -> ([], st)
      (DType ns as l, TWord ty) -> (declare ns as l ty, DSkip)
      (DType ns as l, TSym ';') -> (declare ns as l "", fresh)
      (DType ns as l, _) -> (declare ns as l "", DSkip)
      (DSkip, _) -> ([], DSkip)
      where
        fresh = DStart [] [] 0
        isType = \case
          DType {} -> True
          _ -> False
        declare ns as l ty = [EVar owner (Var n ty as) l | n <- reverse ns]

    -- one token of a TYPE block: a name at the outer level, after TYPE or
    -- a semicolon, followed by a colon or EXTENDS
    typeStep :: TState -> TokVal -> [Tok] -> ([Event], TState)
    typeStep st tv rest = case tv of
      TWord w
        | w `elem` ["STRUCT", "UNION"] -> ([], st {tsDepth = tsDepth st + 1, tsSep = False})
        | w `elem` ["END_STRUCT", "END_UNION"] -> ([], st {tsDepth = max 0 (tsDepth st - 1), tsSep = False})
        | outer && tsSep st && namesType -> ([EType w], st {tsSep = False})
      TSym c
        | c == '(' || c == '[' -> ([], st {tsParen = tsParen st + 1, tsSep = False})
        | c == ')' || c == ']' -> ([], st {tsParen = max 0 (tsParen st - 1), tsSep = False})
        | c == ';' -> ([], st {tsSep = outer})
      _ -> ([], st {tsSep = False})
      where
        outer = tsDepth st == 0 && tsParen st == 0
        namesType = case map tVal (take 1 rest) of
          [TSym ':'] -> True
          [TWord "EXTENDS"] -> True
          _ -> False

    assemble :: [Event] -> Decls
    assemble evs =
      let ends = Map.fromList [(i, e) | EPouEnd i e <- evs]
          onLine = Map.fromListWith (flip (++)) [(l, [a]) | EAttrLine l a <- evs]
          withLine l as = as ++ Map.findWithDefault [] l onLine
          varsOf = Map.fromListWith (flip (++)) [(i, [v {vAttrs = withLine l (vAttrs v)}]) | EVar (Just i) v l <- evs]
          pous =
            [ Pou n q (withLine l as) ext s (Map.findWithDefault maxBound i ends) (Map.findWithDefault [] i varsOf)
            | EPou i q parent as ext s l <- evs
            , let n = if isJust parent then T.takeWhileEnd (/= '.') q else q
            ]
       in Decls pous [v {vAttrs = withLine l (vAttrs v)} | EVar Nothing v l <- evs] (Set.fromList [n | EType n <- evs])

-- | The POUs that contain an offset, innermost first, each followed by the
-- function blocks it extends.
scopeAt :: Decls -> Int -> [Pou]
scopeAt d off = concatMap (withBases (50 :: Int)) (sortOn (Down . pStart) [p | p <- dPous d, pStart p <= off, off < pEnd p])
  where
    withBases 0 p = [p]
    withBases k p = p : case pExtends p of
      Nothing -> []
      Just b -> maybe [] (withBases (k - 1)) (listToMaybe [q | q <- dPous d, pQual q == b])

-- | The variable a name means at an offset: a POU's own first, then a GVL's.
lookupVar :: Decls -> Int -> Text -> Maybe Var
lookupVar d off n = listToMaybe [v | v <- concatMap pVars (scopeAt d off) ++ dGlobals d, vName v == n]

pousNamed :: Decls -> Text -> [Pou]
pousNamed d n = [p | p <- dPous d, pName p == n || pQual p == n]

------------------------------------------------------------------------------
-- Conditional pragmas

data Cond
  = CDefined !Text
  | CDefinedVar !Text
  | CDefinedType !Text
  | CDefinedPou !Text
  | CAttrPou !Text !Text
  | CAttrVar !Text !Text
  | CHasType !Text !Text
  | CHasValue !Text !Text
  | CNot !Cond
  | CAnd !Cond !Cond
  | COr !Cond !Cond

data Directive
  = DDefine !Text !Text
  | DUndefine !Text
  | DIf !Int !Text -- ^ the offset of the expression and its text
  | DElsif !Int !Text
  | DElse
  | DEndIf

type Failure = (Int, Text)

-- | Whether a pragma is a conditional-compilation pragma (NX-PRAGMA-13),
-- its words in any case (NX-PRAGMA-1). Other pragmas give Nothing.
directive :: Int -> Text -> Either Failure (Maybe Directive)
directive start inner =
  let (ws, r0) = T.span isSpace inner
      (kw, r1) = T.span isWordChar r0
      at = start + T.length ws + T.length kw
      blankRest what = if T.all isSpace r1 then Right (Just what) else Left (at, "{" <> kw <> "} takes nothing more")
      name what = case T.span isWordChar (T.stripStart r1) of
        (n, r2) | Just (c, _) <- T.uncons n, isNameStart c -> Right (T.toUpper n, T.strip r2)
        _ -> Left (at, "{" <> what <> "} needs the name of a define")
   in case T.toUpper kw of
        "DEFINE" -> do
          (n, v) <- name kw
          let value = case quoted v of
                Just (s, after) | T.all isSpace after -> s
                _ -> v
          Right (Just (DDefine n value))
        "UNDEFINE" -> do
          (n, v) <- name kw
          if T.null v then Right (Just (DUndefine n)) else Left (at, "{" <> kw <> "} takes one name")
        "IF" -> Right (Just (DIf at r1))
        "ELSIF" -> Right (Just (DElsif at r1))
        "ELSE" -> blankRest DElse
        "END_IF" -> blankRest DEndIf
        _ -> Right Nothing

-- | An open @{IF}@: where it is, whether the text around it is compiled,
-- whether a section was taken, whether the current one is, whether
-- @{ELSE}@ was seen.
data Frame = Frame {frOff :: !Int, frOuter :: !Bool, frTaken :: !Bool, frOn :: !Bool, frElse :: !Bool}

data W = W
  { wDefs :: !(Map.Map Text Text)
  , wFrames :: ![Frame]
  , wCloser :: !(Maybe Text) -- ^ the keyword that ends the current top-level object
  , wOffFrom :: !Int -- ^ where the region left out began, when one is open
  , wBlanks :: ![(Int, Int)] -- ^ reversed
  }

active :: W -> Bool
active w = case wFrames w of
  [] -> True
  f : _ -> frOn f

-- | The pass in file order: defines, the IF stack, the regions left out
-- (NX-PRAGMA-13, NX-PRAGMA-14), and where each top-level object ends, which
-- ends the defines written in it (NX-PRAGMA-3).
walk :: Decls -> [Tok] -> Either Failure [(Int, Int)]
walk decls = go (W Map.empty [] Nothing 0 [])
  where
    go w [] = case wFrames w of
      f : _ -> Left (frOff f, "this {IF} has no {END_IF}")
      [] -> Right (reverse (wBlanks w))
    go w (t : rest) = case tVal t of
      TPragma start inner -> do
        md <- directive start inner
        case md of
          Nothing -> go w rest
          Just d -> do
            w' <- apply w t d
            let was = active w
                now = active w'
                blanks
                  | was && not now = (tStart t, tEnd t) : wBlanks w'
                  | not was && now = (wOffFrom w, tEnd t) : wBlanks w'
                  | was = (tStart t, tEnd t) : wBlanks w'
                  | otherwise = wBlanks w'
                from = if was && not now then tStart t else wOffFrom w
            go w' {wBlanks = blanks, wOffFrom = from} rest
      TWord k | active w -> go (object w k) rest
      _ -> go w rest

    object w k = case wCloser w of
      Nothing
        | Just c <- Map.lookup k topObjects -> w {wCloser = Just c}
        | k `Set.member` varKeywords || k == "VAR_CONFIG" || k == "VAR_ACCESS" -> w {wCloser = Just "END_VAR"}
        | otherwise -> w
      Just c
        | c == k -> w {wCloser = Nothing, wDefs = Map.empty}
        | otherwise -> w

    topObjects =
      Map.fromList
        [ ("PROGRAM", "END_PROGRAM")
        , ("FUNCTION", "END_FUNCTION")
        , ("FUNCTION_BLOCK", "END_FUNCTION_BLOCK")
        , ("TYPE", "END_TYPE")
        , ("INTERFACE", "END_INTERFACE")
        , ("CONFIGURATION", "END_CONFIGURATION")
        ]

    apply w t = \case
      DDefine n v
        | active w -> Right w {wDefs = Map.insert n v (wDefs w)}
        | otherwise -> Right w
      DUndefine n
        | active w -> Right w {wDefs = Map.delete n (wDefs w)}
        | otherwise -> Right w
      DIf at e
        | active w -> do
            v <- condition w at e
            Right w {wFrames = Frame (tStart t) True v v False : wFrames w}
        | otherwise -> Right w {wFrames = Frame (tStart t) False True False False : wFrames w}
      DElsif at e -> case wFrames w of
        [] -> Left (tStart t, "{ELSIF} without {IF}")
        f : fs
          | frElse f -> Left (tStart t, "{ELSIF} after {ELSE}")
          | not (frOuter f) -> Right w
          | otherwise -> do
              v <- condition w at e
              let on = not (frTaken f) && v
              Right w {wFrames = f {frTaken = frTaken f || on, frOn = on} : fs}
      DElse -> case wFrames w of
        [] -> Left (tStart t, "{ELSE} without {IF}")
        f : fs
          | frElse f -> Left (tStart t, "a second {ELSE} for the same {IF}")
          | otherwise -> Right w {wFrames = f {frTaken = True, frOn = frOuter f && not (frTaken f), frElse = True} : fs}
      DEndIf -> case wFrames w of
        [] -> Left (tStart t, "{END_IF} without {IF}")
        _ : fs -> Right w {wFrames = fs}

    condition w at e = do
      c <- parseCond at e
      Right (eval decls (wDefs w) at c)

-- | The value of a condition at an offset (NX-PRAGMA-14, NX-PRAGMA-15).
eval :: Decls -> Map.Map Text Text -> Int -> Cond -> Bool
eval d defs off = go
  where
    go = \case
      CDefined n -> Map.member n defs
      CDefinedVar n -> isJust (lookupVar d off n)
      CDefinedType n -> Set.member n (dTypes d)
      CDefinedPou n -> not (null (pousNamed d n))
      CAttrPou n a -> any (elem a . pAttrs) (pousNamed d n)
      CAttrVar n a -> maybe False (elem a . vAttrs) (lookupVar d off n)
      CHasType n ty -> maybe False (hasType ty . vType) (lookupVar d off n)
      CHasValue n s -> Map.lookup n defs == Just s
      CNot c -> not (go c)
      CAnd a b -> go a && go b
      COr a b -> go a || go b

-- | Whether a declared type (its first word, in upper case; empty for an
-- inline enumeration) belongs to the type or ANY_ group named in @hastype@
-- (NX-TYPE-84, NX-TYPE-85: the IEC 61131-3 hierarchy, with LTIME in
-- ANY_MAGNITUDE as IEC's ANY_DURATION).
hasType :: Text -> Text -> Bool
hasType query declared = case Map.lookup query groups of
  Just members -> canon declared `elem` members
  Nothing
    | query == "ANY" -> True
    | query == "ANY_ELEMENTARY" -> elementary
    | query == "ANY_DERIVED" -> not elementary
    | otherwise -> canon query == canon declared
  where
    elementary = canon declared `elem` anyElementary
    canon = \case
      "TOD" -> "TIME_OF_DAY"
      "DT" -> "DATE_AND_TIME"
      x -> x
    anyInt = ["SINT", "INT", "DINT", "LINT", "USINT", "UINT", "UDINT", "ULINT"]
    anyReal = ["REAL", "LREAL"]
    anyNum = anyInt ++ anyReal
    anyMagnitude = anyNum ++ ["TIME", "LTIME"]
    anyBit = ["BOOL", "BYTE", "WORD", "DWORD", "LWORD"]
    anyString = ["STRING", "WSTRING"]
    anyDate = ["DATE", "TIME_OF_DAY", "DATE_AND_TIME"]
    anyElementary = anyMagnitude ++ anyBit ++ anyString ++ anyDate
    groups =
      Map.fromList
        [ ("ANY_INT", anyInt)
        , ("ANY_REAL", anyReal)
        , ("ANY_NUM", anyNum)
        , ("ANY_MAGNITUDE", anyMagnitude)
        , ("ANY_BIT", anyBit)
        , ("ANY_STRING", anyString)
        , ("ANY_DATE", anyDate)
        ]

------------------------------------------------------------------------------
-- The expression of {IF} and {ELSIF}

data ETok = EWord !Int !Text | EStr !Int !Text | ESym !Int !Char

etokOff :: ETok -> Int
etokOff = \case
  EWord o _ -> o
  EStr o _ -> o
  ESym o _ -> o

-- | The expression's tokens: names (in upper case), quoted strings and
-- @( ) , : .@.
exprTokens :: Int -> Text -> Either Failure [ETok]
exprTokens start = go start
  where
    go !o t = case T.uncons t of
      Nothing -> Right []
      Just (c, r)
        | isSpace c -> go (o + 1) r
        | isNameStart c ->
            let (a, b) = T.span isWordChar t
             in (EWord o (T.toUpper a) :) <$> go (o + T.length a) b
        | c `elem` ("(),:." :: String) -> (ESym o c :) <$> go (o + 1) r
        | c == '\'' || c == '"' -> case quoted t of
            Just (s, after) -> (EStr o s :) <$> go (o + T.length t - T.length after) after
            Nothing -> Left (o, "this string is not closed inside the pragma")
        | otherwise -> Left (o, "'" <> T.singleton c <> "' cannot stand in the condition of a conditional pragma")

-- | @expr := term {OR term}; term := factor {AND factor};
-- factor := NOT factor | ( expr ) | operator@ (NX-PRAGMA-15).
parseCond :: Int -> Text -> Either Failure Cond
parseCond start text = do
  toks <- exprTokens start text
  (c, rest) <- orE toks
  case rest of
    [] -> Right c
    t : _ -> Left (etokOff t, "expected AND, OR or the end of the condition")
  where
    endOff = start + T.length text
    offOf = \case
      [] -> endOff
      t : _ -> etokOff t
    orE ts = do
      (a, r) <- andE ts
      case r of
        EWord _ "OR" : r' -> do
          (b, r'') <- orE r'
          Right (COr a b, r'')
        _ -> Right (a, r)
    andE ts = do
      (a, r) <- notE ts
      case r of
        EWord _ "AND" : r' -> do
          (b, r'') <- andE r'
          Right (CAnd a b, r'')
        _ -> Right (a, r)
    notE = \case
      EWord _ "NOT" : r -> do
        (a, r') <- notE r
        Right (CNot a, r')
      ts -> atom ts
    atom = \case
      ESym _ '(' : r -> do
        (a, r') <- orE r
        r'' <- sym ')' r'
        Right (a, r'')
      EWord _ "DEFINED" : r -> do
        r1 <- sym '(' r
        (c, r2) <- case r1 of
          EWord _ k : ESym _ ':' : r' -> do
            (n, r'') <- name r'
            case k of
              "VARIABLE" -> Right (CDefinedVar n, r'')
              "TYPE" -> Right (CDefinedType n, r'')
              "POU" -> Right (CDefinedPou n, r'')
              _ -> Left (offOf r1, "defined takes a name, variable:name, type:name or pou:name")
          _ -> do
            (n, r') <- ident r1
            Right (CDefined n, r')
        r3 <- sym ')' r2
        Right (c, r3)
      EWord _ "HASATTRIBUTE" : r -> do
        r1 <- sym '(' r
        (mk, r2) <- case r1 of
          EWord _ "POU" : ESym _ ':' : r' -> Right (CAttrPou, r')
          EWord _ "VARIABLE" : ESym _ ':' : r' -> Right (CAttrVar, r')
          _ -> Left (offOf r1, "hasattribute takes pou:name or variable:name, then the attribute")
        (n, r3) <- name r2
        r4 <- sym ',' r3
        (a, r5) <- str r4
        r6 <- sym ')' r5
        Right (mk n (T.toUpper a), r6)
      EWord _ "HASTYPE" : r -> do
        r1 <- sym '(' r
        r2 <- case r1 of
          EWord _ "VARIABLE" : ESym _ ':' : r' -> Right r'
          _ -> Left (offOf r1, "hastype takes variable:name, then a type")
        (n, r3) <- name r2
        r4 <- sym ',' r3
        (ty, r5) <- ident r4
        r6 <- sym ')' r5
        Right (CHasType n ty, r6)
      EWord _ "HASVALUE" : r -> do
        r1 <- sym '(' r
        (n, r2) <- ident r1
        r3 <- sym ',' r2
        (s, r4) <- str r3
        r5 <- sym ')' r4
        Right (CHasValue n s, r5)
      ts -> Left (offOf ts, "expected defined, hasattribute, hastype, hasvalue, NOT or a parenthesis")
    sym c = \case
      ESym _ c' : r | c == c' -> Right r
      ts -> Left (offOf ts, "expected '" <> T.singleton c <> "'")
    ident = \case
      EWord _ n : r -> Right (n, r)
      ts -> Left (offOf ts, "expected a name")
    name ts = do
      (n, r) <- ident ts
      case r of
        ESym _ '.' : r' -> do
          (m, r'') <- name r'
          Right (n <> "." <> m, r'')
        _ -> Right (n, r)
    str = \case
      EStr _ s : r -> Right (s, r)
      ts -> Left (offOf ts, "expected a quoted string")
